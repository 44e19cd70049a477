/* test_tissue_contact.c: the thread's contact with an elastic pad's
 * deformed surface (the pad's moving surface mesh, sim/contact/mesh.h, made
 * by tissue_coupling_surface and put on the pad by tissue_coupling_step):
 * the moving mesh's tree against the fixed mesh's grid on the same
 * triangles, a wire resting under gravity on a soft slab (the pad's holders
 * take the wire's weight beside the pad's own; the wire lies on the sunken
 * top, not on the box's), a point load pressing a wire into the pad (a dent,
 * the wire's lowest point on the dented surface), the wound's slit left
 * out of the surface, and a rigid pad touched as its box; a suture draped
 * over the held, ridged edge of a stretched pad, the surface rounded there. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "sim/contact/contact.h"
#include "sim/contact/friction.h"
#include "sim/contact/mesh.h"
#include "sim/contact/surface.h"
#include "sim/contact/surface_contact.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "sim/scheme_implicit.h"
#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_coupling.h"
#include "test.h"
#include "test_pad_reaction.h"
#include "test_scene_run.h"

/* The moving mesh's tree answers what the fixed mesh's grid does on the
 * same triangles: the pad's surface, deformed, at 3000 points about it. */
static void tree_against_grid(void)
{
    static const char scene[] =
        "[rod]\nlength = 0.01\ndiameter = 0.001\ndensity = 1000\nyoungs_modulus = 1e9\nshear_modulus = 4e8\nnodes = 11\norigin = -0.005 0 0.01\n"
        "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.01\n"
        "[surface]\nshape = box\ncenter = 0 0 0\nsize = 0.04 0.03 0.008\ntissue = yes\n"
        "model = elastic\nelement_size = 0.005\n";
    rod_model m;
    char err[1024] = "";
    if (!check(read_scene_text(scene, &m, err, sizeof err) == 0, "the pad scene reads (%s)", err))
        return;
    tissue_solid *t = m.surfaces[0].solid;
    rod_mesh *moving = m.surfaces[0].mesh;
    /* a bump: the top pushed up by a smooth load, then the mesh moved there */
    const double *rest = tissue_rest_positions(t);
    double *x = tissue_positions(t);
    for (int n = 0; n < tissue_node_count(t); n++)
        x[3 * n + 2] += 0.002 * exp(-(rest[3 * n] * rest[3 * n] + rest[3 * n + 1] * rest[3 * n + 1]) /
                                    1e-4) * (rest[3 * n + 2] + 0.004) / 0.008;
    rod_mesh_move(moving, x, 0.0);
    rod_mesh_move(moving, x, 0.5); /* not moved over 0.5 s: at rest */
    const int nt = rod_mesh_triangle_count(moving), *tri = rod_mesh_triangles(moving);
    double *soup = malloc((size_t)nt * 9 * sizeof(double));
    for (int k = 0; k < nt; k++)
        for (int c = 0; c < 3; c++) memcpy(&soup[9 * k + 3 * c], &x[3 * tri[3 * k + c]], 3 * sizeof(double));
    rod_mesh *fixed = rod_mesh_create(soup, nt, NULL, err, sizeof err);
    free(soup);
    if (!check(fixed != NULL, "the same triangles as a fixed mesh (%s)", err)) {
        rod_model_release(&m);
        return;
    }
    unsigned seed = 12345u;
    double worst = 0.0, worst_w = 0.0;
    int signs = 0, inside = 0;
    for (int k = 0; k < 3000; k++) {
        double p[3];
        for (int c = 0; c < 3; c++) {
            seed = seed * 1103515245u + 12345u;
            p[c] = ((seed >> 8) / 16777216.0 - 0.5) * (c == 2 ? 0.02 : 0.06);
        }
        const double a = rod_mesh_distance(moving, p, NULL, NULL), b = rod_mesh_distance(fixed, p, NULL, NULL);
        worst = fmax(worst, fabs(fabs(a) - fabs(b)));
        signs += (a < 0.0) != (b < 0.0);
        inside += a < 0.0;
        int tt;
        double w[3], v[3];
        rod_mesh_nearest(moving, p, &tt, w);
        rod_mesh_point_velocity(moving, tt, w, v);
        worst_w = fmax(worst_w, fabs(v[0]) + fabs(v[1]) + fabs(v[2]));
    }
    check_abs("the tree's distance against the grid's at 3000 points, largest difference (m)",
              worst, 0.0, 1e-15);
    check(signs == 0 && inside > 100, "the same side at every point (%d differ; %d inside)", signs,
          inside);
    check_abs("the surface's velocity, unmoved over 0.5 s (m/s)", worst_w, 0.0, 0.0);
    /* moved by 1 mm up over 0.1 s: 0.01 m/s at every point */
    for (int n = 0; n < tissue_node_count(t); n++) x[3 * n + 2] += 0.001;
    rod_mesh_move(moving, x, 0.6);
    double p[3] = {0.003, -0.002, 0.01}, v[3], w[3];
    int tt;
    rod_mesh_nearest(moving, p, &tt, w);
    rod_mesh_point_velocity(moving, tt, w, v);
    check_rel("the surface's velocity after a 1 mm rise over 0.1 s (m/s, z)", v[2], 0.01, 1e-9);
    rod_mesh_destroy(fixed);
    rod_model_release(&m);
}

/* A steel wire (2 mm thick, 24 mm long, free ends) laid on a soft slab (E 2
 * kPa, 40 x 30 x 8 mm, held at its bottom) under gravity: the slab sinks
 * under its own weight and the wire's (some 0.2 mm). */
static const char rest_scene[] =
    "[rod]\nlength = 0.024\ndiameter = 0.002\ndensity = 7800\nyoungs_modulus = 2e11\n"
    "shear_modulus = 8e10\nnodes = 25\norigin = -0.012 0.002 0.0012\n"
    "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1\n"
    "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 3\n[ends]\nroot = free\ntip = free\n"
    "[surface]\nshape = box\ncenter = 0 0 -0.004\nsize = 0.04 0.03 0.008\ntissue = yes\n"
    "friction = 0.3\nmodel = elastic\nyoungs_modulus = 2e3\nelement_size = 0.004\n";

/* Each node's gap to the pad's surface where the pad is now (m: the
 * distance less the radius); the largest |gap| and the nodes' lowest z. */
static void gaps(const rod_model *m, const rod_state *s, double *largest, double *lowest, int *low)
{
    rod_mesh *mesh = m->surfaces[0].mesh;
    rod_mesh_move(mesh, tissue_positions(m->surfaces[0].solid), s->time);
    *largest = 0.0;
    *lowest = INFINITY;
    for (int b = 0; b < m->nodes; b++) {
        const double *p = &s->position[3 * b];
        *largest = fmax(*largest, fabs(rod_mesh_distance(mesh, p, NULL, NULL) - 0.5 * m->diameter));
        if (p[2] < *lowest) {
            *lowest = p[2];
            *low = b;
        }
    }
}

static void wire_at_rest(void)
{
    rod_model m;
    char err[1024] = "";
    if (!check(read_scene_text(rest_scene, &m, err, sizeof err) == 0, "the rest scene reads (%s)", err))
        return;
    rod_state *s = rod_state_create(&m);
    const double r = 0.5 * m.diameter;
    if (!check(s && run_steps(&m, s, 1000, 0.001) == 0, "the wire settles on the slab in 1 s")) {
        rod_state_destroy(s);
        rod_model_release(&m);
        return;
    }
    tissue_solid *t = m.surfaces[0].solid;
    const double weight = m.mass_per_length * m.length * 9.81; /* N */
    double load = 0.0, speed = 0.0;
    const double *f = tissue_external_forces(t);
    for (int n = 0; n < tissue_node_count(t); n++) load -= f[3 * n + 2];
    double held = 0.0;
    for (int b = 0; b < m.nodes; b++) {
        speed = fmax(speed, fabs(s->velocity[3 * b + 2]));
        held += s->surface_force[3 * b + 2];
    }

    check(speed < 1e-4, "the wire is at rest (largest speed %.3g m/s, below 1e-4)", speed);
    check_rel("the surface's force on the wire (N, up) against its weight", held, weight, 1e-4);
    check_rel("the load on the pad (N, down) against the wire's weight", load, weight, 1e-4);
    check_rel("the pad's holders take the wire's weight beside the pad's own (N)",
              pad_reaction(t, 9.81), weight, 1e-4);
    double largest, lowest;
    int low = 0;
    gaps(&m, s, &largest, &lowest, &low);
    check_abs("the wire on the deformed top: largest |gap| of a node (m), within 1 % of the "
              "radius", largest, 0.0, 0.01 * r);
    printf("note: the vertices' compliance scaled by %.3g (the give along the wire)\n",
           rod_mesh_compliance_scale(m.surfaces[0].mesh));
    /* the contact's velocity maps, the pad's give and friction folded in,
     * in Newton's Jacobian against central differences */
    int column = -1;
    double floor = 0.0;
    const double e = rod_implicit_contact_jacobian_error(&m, s, 0.001, 0.003, &column, &floor);
    check(e <= 1e-4 && floor < 1e-2, "the Jacobian with the pad's surface vs central differences, "
          "largest difference %.3e of its column's largest entry (column %d; tolerance 1e-4; "
          "the differences' rounding resolves %.1e of it)", e, column, floor);
    /* the box's top is z = 0: the wire's centreline would be at r there */
    const double *x = tissue_positions(t), *rest = tissue_rest_positions(t);
    double sunk = 0.0;
    for (int n = 0; n < tissue_node_count(t); n++)
        if (fabs(rest[3 * n]) < 1e-9 && rest[3 * n + 2] > -1e-9 && fabs(rest[3 * n + 1] - 0.002) < 0.0021)
            sunk = fmin(sunk, x[3 * n + 2]);
    check(lowest < r - 0.1 * r && sunk < -0.1 * r,
          "below the box's top: the wire's lowest centre %.4g mm (%.4g mm on the box), the top "
          "under it %.4g mm", 1e3 * lowest, 1e3 * r, 1e3 * sunk);
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* A light wire across the pad (stiffer than the thread, 0.5 mm steel), gravity
 * off, a point load F = 0.2 N pressing its middle into a pad of E 50 kPa. */
static const char dent_scene[] =
    "[rod]\nlength = 0.024\ndiameter = 0.0005\ndensity = 7800\nyoungs_modulus = 2e11\n"
    "shear_modulus = 8e10\nnodes = 25\norigin = -0.012 0.001 0.00025\n"
    "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1\n"
    "[loads]\nlinear_damping = 1\n[physics]\ngravity = off\n[ends]\nroot = free\ntip = free\n"
    "[point_load]\ns = 0.012\nforce = 0 0 -0.2\n"
    "[surface]\nshape = box\ncenter = 0 0 -0.004\nsize = 0.04 0.03 0.008\ntissue = yes\n"
    "friction = 0.3\nmodel = elastic\nyoungs_modulus = 5e4\nelement_size = 0.004\n";

static void point_load_dent(void)
{
    rod_model m;
    char err[1024] = "";
    if (!check(read_scene_text(dent_scene, &m, err, sizeof err) == 0, "the dent scene reads (%s)", err))
        return;
    rod_state *s = rod_state_create(&m);
    const double r = 0.5 * m.diameter, F = 0.2;
    if (!check(s && run_steps(&m, s, 1000, 0.001) == 0, "the loaded wire settles in 1 s")) {
        rod_state_destroy(s);
        rod_model_release(&m);
        return;
    }
    tissue_solid *t = m.surfaces[0].solid;
    double load = 0.0;
    const double *f = tissue_external_forces(t);
    for (int n = 0; n < tissue_node_count(t); n++) load -= f[3 * n + 2];
    check_rel("the load on the pad (N, down) against the point load", load, F, 1e-3);
    check_rel("the pad's holders take the point load (N)", pad_reaction(t, 0.0), F, 1e-3);
    double largest, lowest;
    int low = 0;
    gaps(&m, s, &largest, &lowest, &low);
    /* the surface at the lowest node: its distance to the pad's surface */
    const double gap = rod_mesh_distance(m.surfaces[0].mesh, &s->position[3 * low], NULL, NULL) - r;
    check_abs("the wire's lowest node on the dented surface: its gap (m), within 1 % of the radius",
              gap, 0.0, 0.01 * r);
    check(low == 12, "the lowest node is the loaded one (%d)", low);
    printf("note: the vertices' compliance scaled by %.3g\n", rod_mesh_compliance_scale(m.surfaces[0].mesh));
    check(lowest < r - 20.0 * 0.01 * r,
          "the dent: the lowest centre %.4g mm, %.3g mm below where the box's top holds it",
          1e3 * lowest, 1e3 * (r - lowest));
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* The wound's slit: its faces are not in the surface (a wound pad's surface
 * has rims: the slit's opening), and a point in the open gap is outside. */
static void slit_left_out(void)
{
    static const char scene[] =
        "[rod]\nlength = 0.01\ndiameter = 0.0003\ndensity = 1000\nyoungs_modulus = 1e9\nshear_modulus = 4e8\nnodes = 11\norigin = -0.005 0 0.01\n"
        "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.01\n[physics]\ngravity = off\n"
        "[surface]\nshape = box\ncenter = 0 0 -0.004\nsize = 0.04 0.03 0.008\ntissue = yes\n"
        "model = elastic\nyoungs_modulus = 6e5\nelement_size = 0.006\nheld = bottom sides\n"
        "pretension = 0 0.3 0\nwound = -0.012 0 0.012 0 0.002\n";
    rod_model m;
    char err[1024] = "";
    if (!check(read_scene_text(scene, &m, err, sizeof err) == 0, "the wound scene reads (%s)", err))
        return;
    tissue_solid *t = m.surfaces[0].solid;
    rod_mesh *mesh = m.surfaces[0].mesh;
    rod_mesh_move(mesh, tissue_positions(t), 0.0);
    const int nt = rod_mesh_triangle_count(mesh), *tri = rod_mesh_triangles(mesh);
    const double *rest = tissue_rest_positions(t);
    int on_plane = 0;
    for (int k = 0; k < nt; k++)
        on_plane += rest[3 * tri[3 * k] + 1] == 0.0 && rest[3 * tri[3 * k + 1] + 1] == 0.0 &&
                    rest[3 * tri[3 * k + 2] + 1] == 0.0;
    check(on_plane == 0, "no triangle of the surface lies on the slit's plane (%d do)", on_plane);
    const double gap = tissue_coupling_gap_at(t, (const double[3]){0.0, 0.0, 0.0});
    const double p[3] = {0.0, 0.0, -0.0005};
    const double d = rod_mesh_distance(mesh, p, NULL, NULL);
    check(gap > 1e-3 && d > 0.0,
          "0.5 mm down in the open wound (gap %.3g mm) is outside the surface (%.3g mm from it)",
          1e3 * gap, 1e3 * d);
    /* rounded to 0.5 mm: the rounding takes material off the edges and the
     * lips' rims are rounded away from the opening, so the point in it is
     * no nearer; a point over the top away from the wound and the pad's
     * edges is as far as before */
    const double q[3] = {0.008, 0.008, 0.0}, over = rod_mesh_distance(mesh, q, NULL, NULL);
    rod_mesh_set_rounding(mesh, 0.0005);
    const double d_round = rod_mesh_distance(mesh, p, NULL, NULL);
    check(d_round >= d, "rounded to 0.5 mm: the point in the open wound is no nearer the surface "
          "(%.4g mm, sharp %.4g mm)", 1e3 * d_round, 1e3 * d);
    check_abs("rounded to 0.5 mm: a point over the top, its distance (m) against the sharp "
              "surface's", rod_mesh_distance(mesh, q, NULL, NULL), over, 1e-6);
    rod_model_release(&m);
}

/* The wire resting on the slab while the slab's held bottom is carried
 * along x at 10 mm/s: the friction against the moving surface carries the
 * wire with it (against a still surface the wire would stay behind). */
static void wire_carried(void)
{
    rod_model m;
    char err[1024] = "";
    if (!check(read_scene_text(rest_scene, &m, err, sizeof err) == 0, "the carried scene reads (%s)", err))
        return;
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    rod_report report;
    memset(&report, 0, sizeof report);
    const double dt = 0.001, speed = 0.01; /* s, m/s */
    int ok = s && rod_solver_init(&solver, &m, err, sizeof err) == 0;
    if (!check(ok, "the carried scene's solver (%s)", err)) {
        rod_state_destroy(s);
        rod_model_release(&m);
        return;
    }
    tissue_solid *t = m.surfaces[0].solid;
    const double *rest = tissue_rest_positions(t);
    double x0 = 0.0, x1 = 0.0;
    for (int k = 0; k < 600 && ok; k++) {
        if (k >= 300) /* the bottom carried along from 0.3 s */
            for (int q = 0; q < tissue_node_count(t); q++)
                if (rest[3 * q + 2] < -0.008 + 1e-9) {
                    const double target[3] = {rest[3 * q] + speed * (k - 299) * dt, rest[3 * q + 1],
                                              rest[3 * q + 2]};
                    tissue_hold(t, q, 7u, target);
                }
        ok = rod_solver_step(&solver, &m, s, dt, &report) == ROD_OK;
        if (k == 399 || k == 599) {
            double mean = 0.0;
            for (int b = 0; b < m.nodes; b++) mean += s->position[3 * b] / m.nodes;
            if (k == 399) x0 = mean;
            else x1 = mean;
        }
    }
    rod_solver_release(&solver);
    if (check(ok, "the carried run steps (%s)", report.message))
        check_rel("the wire carried by the moving surface: its mean velocity along x over the "
                  "last 0.2 s (m/s) against the bottom's", (x1 - x0) / 0.2, speed, 5e-3);
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* A rigid pad (model = rigid) has no surface mesh: its contact is the
 * box's, as before (the shipped scenes' outputs stay byte for byte). */
static void rigid_pad_is_the_box(void)
{
    char text[sizeof rest_scene + 16];
    char *at = strstr(strcpy(text, rest_scene), "model = elastic");
    memcpy(at, "model = rigid  ", 15);
    rod_model m;
    char err[1024] = "";
    if (!check(read_scene_text(text, &m, err, sizeof err) == 0, "the rigid pad reads (%s)", err)) return;
    rod_state *s = rod_state_create(&m);
    check(m.surfaces[0].solid == NULL && m.surfaces[0].mesh == NULL,
          "a rigid pad has neither a solid nor a surface mesh");
    if (s && run_steps(&m, s, 300, 0.001) == 0) {
        double lowest = INFINITY, held = 0.0;
        for (int b = 0; b < m.nodes; b++) {
            lowest = fmin(lowest, s->position[3 * b + 2]);
            held += s->surface_force[3 * b + 2];
        }
        check_abs("on the rigid box's top: the wire's lowest centre (m) at its radius", lowest,
                  0.5 * m.diameter, 0.01 * 0.5 * m.diameter);
        check_rel("the box holds the wire's weight (N)", held, m.mass_per_length * m.length * 9.81,
                  1e-6);
    }
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* The friction law on a moving surface, node by node: a node pressed onto
 * the pad's top while the surface moves along x at u (set by hand, as a
 * moving surface's velocity) is carried along at the creep law's relative
 * speed when the friction holds (its velocity along x comes to u less the
 * creep), and slides with mu times the force across, pulled along +x,
 * when the surface moves too fast for it; on a surface that gives as much
 * as the node, the two meet halfway. */
static void friction_relative_velocity(void)
{
    rod_model m;
    char err[1024] = "";
    if (!check(read_scene_text(rest_scene, &m, err, sizeof err) == 0, "the law's pad reads (%s)", err))
        return;
    const int n = m.nodes, b = 5;
    const double r = 0.5 * m.diameter, dt = 1e-3, push = 1.0, theta = m.options.theta;
    double *pos0 = calloc((size_t)n * 3, sizeof(double)), *vel1 = calloc((size_t)n * 3, sizeof(double)),
           *vbar = calloc((size_t)n * 3, sizeof(double));
    for (int i = 0; i < n; i++) pos0[3 * i + 2] = 0.05; /* far above */
    rod_surface view;
    const rod_surface *sf = rod_surface_contact_view(&m.surfaces[0], &view);
    double p[3] = {0.0, 0.002, 0.0}, normal[3];
    rod_mesh_move(m.surfaces[0].mesh, tissue_positions(m.surfaces[0].solid), 0.0);
    p[2] -= rod_surface_gap(sf, p, r, normal, NULL); /* touching the deformed top */
    memcpy(&pos0[3 * b], p, sizeof p);
    const int held[2] = {0, 0};
    rod_contact c;
    /* m/s: held by the friction, sliding, held on a compliant surface */
    const double speeds[3] = {0.002, 2.0, 0.002}, a = dt * theta * push;
    for (int k = 0; k < 3; k++) {
        if (!check(rod_contact_create(&c, &m, pos0, vel1, vbar, held, 0) == 0, "contact made"))
            break;
        surface_contact_prepare(&c, &m);
        c.surface_motion[8 * (size_t)b] = speeds[k]; /* the surface moves along x */
        /* the third: the surface gives as much as the node (m/N) */
        c.surface_motion[8 * (size_t)b + 3] = k == 2 ? a : 0.0;
        vel1[3 * b + 2] = -0.1; /* pressed in at 0.1 m/s */
        vel1[3 * b] = vel1[3 * b + 1] = 0.0;
        for (int q = 0; q < 3; q++) vbar[3 * b + q] = theta * vel1[3 * b + q];
        surface_contact_node(&c, &m, b, push, dt);
        const double *f = &c.surface_force[3 * b], lambda = f[0] * normal[0] + f[1] * normal[1] + f[2] * normal[2];
        const double mu = m.surfaces[0].friction, along = vel1[3 * b];
        if (k == 0) {
            /* held: the relative speed is the creep law's root at the
             * friction's capacity push mu lambda */
            const double creep = contact_creep_speed(speeds[k], push * mu * lambda);
            check_rel("carried by the moving surface: the node's velocity along it (m/s)", along,
                      speeds[k] - creep, 1e-6);
            check(creep < 0.05 * speeds[k], "the relative speed left is the creep, %.3g of u",
                  creep / speeds[k]);
        } else if (k == 2) {
            /* the friction's reaction drags the surface back as much as it
             * drags the node on: they meet halfway (push_t = 2 push) */
            const double creep = contact_creep_speed(speeds[k], 2.0 * push * mu * lambda);
            check_rel("on a surface as compliant as the node: the node's velocity along it (m/s), "
                      "half the surface's less the creep", along, 0.5 * (speeds[k] - creep), 1e-6);
        } else {
            check_rel("sliding: the friction pulls along the surface's motion with mu times the "
                      "force across (N)", f[0], mu * lambda, 1e-3);
            check(along > 0.0 && along < speeds[k], "the node is dragged along, slower than the "
                  "surface (%.4g of %.4g m/s)", along, speeds[k]);
        }
        check(c.pad_force && fabs(c.pad_force[3 * b] - f[0]) < 1e-15 && fabs(c.pad_force[3 * b + 2] - f[2]) < 1e-15,
              "the pad's share is the node's whole surface force");
        rod_contact_destroy(&c);
    }
    free(pos0);
    free(vel1);
    free(vbar);
    rod_model_release(&m);
}

/* A suture (nylon, 0.3 mm) draped over the held front edge of a pad
 * stretched 30 % across (E 0.6 MPa, held at its bottom and sides): its root
 * held 2.2 mm above the top (so that it starts clear of the settled pad's
 * stretched edge, at y = -19.5 mm), its tip pulled down by 0.3 N (a weight
 * hanging on it), friction 0.3. The stretched top sinks between the held sides, so the
 * held edge is a ridge (the top slopes up to it, the side falls from it).
 * `rounding` (m) rounds the surface's convex edges. Returns, through
 * *cut, how deep (m) a point of a segment between nodes reaches into the
 * solid (0: none), and through *drift the nodes' largest |x| (m). */
static const char edge_scene[] =
    "[rod]\nlength = 0.06\ndiameter = 0.0003\ndensity = 1140\nyoungs_modulus = 1e9\n"
    "shear_modulus = 0.37e9\nnodes = 41\norigin = 0 0 0.0022\ndirection = 0 -1 -0.1\n"
    "[ends]\nroot = pinned\ntip = free\n[tip]\nforce = 0 0 -0.3\nframe = global\n"
    "[solver]\nscheme = implicit\ndt = 0.000834\nduration = 1\n"
    "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 2e-3\n"
    "[surface]\nshape = box\ncenter = 0 0 -0.004\nsize = 0.04 0.03 0.008\nfriction = 0.3\n"
    "tissue = yes\nmodel = elastic\nyoungs_modulus = 6e5\npoisson_ratio = 0.45\n"
    "element_size = 0.006\nheld = bottom sides\npretension = 0 0.3 0\n";

/* What all the pad's holders (bottom and sides) take upwards (N) less the
 * pad's own weight. */
static double pad_support(tissue_solid *t, double g)
{
    const double *mass = tissue_node_masses(t);
    double sum = 0.0;
    for (int n = 0; n < tissue_node_count(t); n++) {
        double r[3];
        tissue_reaction(t, n, r);
        sum += r[2] - mass[n] * g;
    }
    return sum;
}

static int drape(double rounding, rod_model *m, rod_state **s, double *cut, double *drift,
                 double *before)
{
    char text[2048], err[1024] = "";
    snprintf(text, sizeof text, "%srounding = %.17g\n", edge_scene, rounding);
    *s = NULL;
    if (!check(read_scene_text(text, m, err, sizeof err) == 0, "the edge scene reads (%s)", err))
        return -1;
    *before = pad_support(m->surfaces[0].solid, 9.81);
    *s = rod_state_create(m);
    if (!*s || run_steps(m, *s, 1200, 0.000834) != 0) return -1;
    rod_mesh *mesh = m->surfaces[0].mesh;
    rod_mesh_move(mesh, tissue_positions(m->surfaces[0].solid), (*s)->time);
    const double r = 0.5 * m->diameter;
    *cut = 0.0;
    *drift = 0.0;
    for (int b = 0; b < m->nodes; b++) *drift = fmax(*drift, fabs((*s)->position[3 * b]));
    for (int b = 0; b + 1 < m->nodes; b++)
        for (int q = 1; q < 8; q++) {
            double p[3];
            for (int c = 0; c < 3; c++)
                p[c] = (*s)->position[3 * b + c] +
                       q / 8.0 * ((*s)->position[3 * (b + 1) + c] - (*s)->position[3 * b + c]);
            *cut = fmax(*cut, r - rod_mesh_distance(mesh, p, NULL, NULL));
        }
    return 0;
}

static void draped_over_edge(void)
{
    rod_model m;
    rod_state *s;
    double cut, drift, before;
    const double tip = 0.3; /* N */
    /* the sharp ridge: the nodes rest on its two faces, the segment between
     * them cuts it */
    if (drape(0.0, &m, &s, &cut, &drift, &before) == 0)
        printf("note: over the sharp ridge a segment reaches %.3g mm into the pad (the radius "
               "%.3g mm), the nodes drift %.3g mm sideways\n", 1e3 * cut, 0.5e3 * m.diameter,
               1e3 * drift);
    rod_state_destroy(s);
    rod_model_release(&m);
    const double rounding = 0.001;
    if (!check(drape(rounding, &m, &s, &cut, &drift, &before) == 0,
               "over the edge rounded to 1 mm the draped thread settles in 1 s")) {
        rod_state_destroy(s);
        rod_model_release(&m);
        return;
    }
    double speed = 0.0;
    for (int b = 0; b < m.nodes; b++) speed = fmax(speed, v3_norm(&s->velocity[3 * b]));
    check(speed < 1e-3, "the thread is at rest (largest speed %.3g m/s, below 1e-3)", speed);
    /* what the pad carries: the thread's weight and the tip's load less what
     * the root's holder takes (end_force: the rod's force on it) */
    const double weight = m.mass_per_length * m.length * 9.81;
    const double share = weight + tip + s->end_force[0][2];
    check_rel("the pad's holders take the thread's share (N): its weight and the tip's load "
              "less the root's", pad_support(m.surfaces[0].solid, 9.81) - before, share, 0.03);
    check(share > 0.5 * tip, "most of the load is on the pad's edge (%.3g N of %.3g N)", share,
          weight + tip);
    /* a chord of ds over the edge rounded to R (grown by the radius r) dips
     * ds^2 / (8 (R + r)) below the arc its nodes rest on */
    const double r = 0.5 * m.diameter, ds = m.length / (m.nodes - 1),
                 sag = ds * ds / (8.0 * (rounding + r));
    check(cut < sag, "no segment cuts the rounded edge deeper than a chord's dip: %.3g um into "
          "it (the dip %.3g um)", 1e6 * cut, 1e6 * sag);
    check(drift < 1e-4, "the thread stays in its plane x = 0 (largest |x| %.3g mm)", 1e3 * drift);
    rod_state_destroy(s);
    rod_model_release(&m);
}

int main(void)
{
    draped_over_edge();
    tree_against_grid();
    wire_at_rest();
    point_load_dent();
    slit_left_out();
    rigid_pad_is_the_box();
    friction_relative_velocity();
    wire_carried();
    return test_finish();
}
