/* test_grid_tissue.c: tissue surfaces (tissue = yes, an elastic pad) on a
 * graded grid (scene [rod] refine, sim/rod_grid.h) against independent
 * values:
 *   - a steel wire lying on a soft elastic pad under gravity, the grid
 *     three times as fine over its middle third: the pad carries the
 *     wire's weight rho A L g (the load put on it and what its holders
 *     take), and the wire's and the pad's settled sag against the same
 *     scene on a uniform grid as fine as the graded grid's fine part;
 *   - a thread drawn through a puncture in an elastic pad with friction
 *     (a 30 degree turn at the hole, the hole sliding across the node
 *     where the spacing halves): the root's tension against Coulomb's law
 *     at the hole where the pad has moved it, and against the same pull on
 *     a uniform grid as fine as the graded grid's fine part;
 *   - a needle driven along a circle through a tissue box, the thread
 *     three times as fine over its last 15 mm (the needle's end): the
 *     entry and exit holes where the circle meets the skin (a hand value),
 *     and where a uniform run as fine as the graded grid's fine part makes
 *     them (their points and arc lengths); with the track, the thread
 *     between the holes at the circle's depth;
 *   - a [puncture] beside a graded starting shape moved onto the thread at
 *     its arc length (half the shape's polyline);
 *   - graded scenes with a tissue surface and with an elastic pad run
 *     (rodsim run, exit 0), as does one with tissue and open scissors held
 *     above it (their cuts: test_grid_scissors.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "sim/contact/puncture.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"
#include "sim/rod_set.h"
#include "sim/scene.h"
#include "sim/tissue/tissue.h"
#include "test.h"
#include "test_needle_bite.h"
#include "test_pad_reaction.h"
#include "test_process.h"
#include "test_puncture_pull.h"
#include "test_run_start.h"
#include "test_scene_run.h"

/* ---- a wire lying on a pad ---- */

typedef struct rest_result {
    double weight;  /* N: rho A L g */
    double load;    /* N: the wire's contact loads on the pad, down */
    double holders; /* N: the pad's holders' reaction less its own weight */
    double held;    /* N: the surface's force on the wire, up */
    double speed;   /* m/s: the wire's largest speed */
    double lowest;  /* m: the wire's lowest centre */
    double middle;  /* m: the wire's centre at its middle (s = L / 2) */
    double sunk;    /* m: the pad's top under the wire's middle */
} rest_result;

/* A steel wire (2 mm thick, 24 mm long, free ends) on a soft slab (E 2 kPa,
 * 40 x 30 x 8 mm, held at its bottom) under gravity for 1 s; `grid` the
 * [rod] lines nodes and refine. */
static int wire_on_pad(const char *grid, rest_result *r)
{
    char text[1024], err[1024] = "";
    snprintf(text, sizeof text,
             "[rod]\nlength = 0.024\ndiameter = 0.002\ndensity = 7800\nyoungs_modulus = 2e11\n"
             "shear_modulus = 8e10\n%sorigin = -0.012 0.002 0.0012\n"
             "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1\n"
             "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 3\n[ends]\nroot = free\ntip = free\n"
             "[surface]\nshape = box\ncenter = 0 0 -0.004\nsize = 0.04 0.03 0.008\ntissue = yes\n"
             "friction = 0.3\nmodel = elastic\nyoungs_modulus = 2e3\nelement_size = 0.004\n",
             grid);
    rod_model m;
    if (read_scene_text(text, &m, err, sizeof err)) {
        printf("     the wire's scene: %s\n", err);
        return -1;
    }
    rod_state *s = rod_state_create(&m);
    int rc = s && run_steps(&m, s, 1000, 0.001) == 0 ? 0 : -1;
    if (rc == 0) {
        tissue_solid *t = m.surfaces[0].solid;
        memset(r, 0, sizeof *r);
        r->weight = m.mass_per_length * m.length * 9.81;
        const double *f = tissue_external_forces(t);
        for (int n = 0; n < tissue_node_count(t); n++) r->load -= f[3 * n + 2];
        r->holders = pad_reaction(t, 9.81);
        r->lowest = INFINITY;
        for (int b = 0; b < m.nodes; b++) {
            r->speed = fmax(r->speed, v3_norm(&s->velocity[3 * b]));
            r->held += s->surface_force[3 * b + 2];
            r->lowest = fmin(r->lowest, s->position[3 * b + 2]);
        }
        /* the centre at s = L / 2, between the nodes either side */
        int j = 0;
        double alpha = 0.0;
        puncture_locate(&m, 0.5 * m.length, &j, &alpha);
        r->middle = (1.0 - alpha) * s->position[3 * j + 2] + alpha * s->position[3 * j + 5];
        /* the pad's top nodes under the wire (y 0..4 mm, x within 1 mm of 0) */
        const double *x = tissue_positions(t), *rest = tissue_rest_positions(t);
        for (int n = 0; n < tissue_node_count(t); n++)
            if (fabs(rest[3 * n]) < 1e-3 && rest[3 * n + 2] > -1e-9 &&
                fabs(rest[3 * n + 1] - 0.002) < 0.0021)
                r->sunk = fmin(r->sunk, x[3 * n + 2]);
    }
    rod_state_destroy(s);
    rod_model_release(&m);
    return rc;
}

static void test_wire_on_pad(void)
{
    /* 25 nodes, three times as fine over 8 .. 16 mm: 1.67 mm segments
     * outside, 0.56 mm inside; the uniform grid 0.5 mm (49 nodes) */
    rest_result g, u;
    if (!check(wire_on_pad("nodes = 25\nrefine = 0.008 0.016 3\n", &g) == 0,
               "the wire settles on the pad in 1 s on the graded grid"))
        return;
    check(g.speed < 1e-4, "graded: the wire is at rest (largest speed %.3g m/s, below 1e-4)",
          g.speed);
    check_rel("graded: the load on the pad (N, down) against rho A L g", g.load, g.weight, 1e-4);
    check_rel("graded: the pad's holders take rho A L g beside the pad's own weight (N)",
              g.holders, g.weight, 1e-4);
    check_rel("graded: the pad's force on the wire (N, up) against rho A L g", g.held, g.weight,
              1e-4);
    if (!check(wire_on_pad("nodes = 49\n", &u) == 0, "the wire settles on a uniform grid of 49 "
               "nodes (0.5 mm)"))
        return;
    check_rel("uniform 49 nodes: the load on the pad (N) against rho A L g", u.load, u.weight,
              1e-4);
    /* the sag: the top's 0 less the centre's radius-high rest (m, down) */
    const double r = 0.001;
    check_rel("graded (25 nodes) against uniform (49): the wire's middle sunk below the box's "
              "top (m)", r - g.middle, r - u.middle, 0.02);
    check_rel("graded against uniform: the wire's lowest centre sunk below the box's top (m)",
              r - g.lowest, r - u.lowest, 0.02);
    check_rel("graded against uniform: the pad's top under the wire's middle (m, down)", -g.sunk,
              -u.sunk, 0.02);
}

/* ---- a thread drawn through a puncture in a pad ---- */

#define PULL_LENGTH 0.06
#define PULL_HOLE 0.03

typedef struct pull_result {
    double t_root;    /* N: the root's mean support force over 0.12 .. 0.18 s */
    double reference; /* N: Coulomb's law at the hole, the strands at 0.18 s */
    double slid;      /* m: the puncture's arc length's change */
    double moved;     /* m: the hole's largest move with the pad */
    double miss;      /* m: the largest distance from the hole to the thread */
    int linked;       /* the hole is a point of the pad */
} pull_result;

/* A thread of 60 mm (0.3 mm), its root pulled along -x at 20 mm/s for
 * 0.3 s, through a hole at (30, 0, 0) mm in the face x = 30 mm of an
 * elastic pad (E 500 kPa, 30 x 30 x 40 mm, held at its bottom, gravity
 * off); the tip's load W at 30 degrees above +x ramped over 0.05 s, the
 * tip strand inside the pad. `grid` the [rod] lines nodes and refine. */
static int pull_through_pad(const char *grid, double mu, double w_load, pull_result *r)
{
    const double duration = 0.3, speed = 0.02, turn = M_PI / 6.0, dt = 2e-3;
    char path[512], text[2048], err[1024] = "";
    snprintf(path, sizeof path, "%s/root.csv", test_dir());
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fprintf(f, "t,x,y,z\n");
    for (int k = 0; k <= 6; k++)
        fprintf(f, "%.6f,%.12f,0,0\n", duration * k / 6.0, -speed * duration * k / 6.0);
    fclose(f);
    snprintf(text, sizeof text,
             "[rod]\nlength = %g\ndiameter = 0.0003\ndensity = 850\nyoungs_modulus = 87.5e6\n"
             "shear_modulus = 31.25e6\n%sself_contact = no\n"
             "[ends]\nroot = pinned\nroot_motion = %s\n"
             "[tip]\nforce = %.12g 0 %.12g\nframe = global\nprofile = ramp 0.05\n"
             "[loads]\nlinear_damping = 1e-3\n[physics]\ngravity = off\n"
             "[solver]\nscheme = implicit\ndt = %g\nduration = %g\n"
             "[surface]\nshape = box\ncenter = 0.045 0 0.005\nsize = 0.03 0.03 0.04\n"
             "tissue = yes\nmodel = elastic\nelement_size = 0.004\n"
             "[puncture]\npoint = %g 0 0\nfriction = %g\n",
             PULL_LENGTH, grid, path, w_load * cos(turn), w_load * sin(turn), dt, duration,
             PULL_HOLE, mu);
    rod_model m;
    if (read_scene_text(text, &m, err, sizeof err)) {
        printf("     the pull's scene: %s\n", err);
        return -1;
    }
    memset(r, 0, sizeof *r);
    rod_solver solver;
    rod_state *s = run_start(&m, &solver);
    if (!s) {
        rod_model_release(&m);
        return -1;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    const int steps = (int)lround(duration / dt);
    const double start[3] = {PULL_HOLE, 0.0, 0.0}, s_start = s->puncture[0].s;
    double sum = 0.0, u1[3] = {0}, u2[3] = {0};
    int count = 0, rc = 0;
    for (int k = 1; k <= steps; k++) {
        if (rod_solver_step(&solver, &m, s, dt, &report)) {
            printf("     pull step %d (t = %g s): %s\n", k, s->time, report.message);
            rc = -1;
            break;
        }
        const double *hole = s->puncture[0].point;
        double dist, d[3];
        rod_nearest_arc_length(&m, s->position, hole, &dist);
        r->miss = fmax(r->miss, dist);
        v3_sub(d, hole, start);
        r->moved = fmax(r->moved, v3_norm(d));
        if (s->time >= 0.4 * duration - 1e-9 && s->time <= 0.6 * duration + 1e-9) {
            sum += v3_norm(s->end_force[0]);
            count++;
            /* the strands' directions away from the hole where it is now */
            strand_directions(s->position, m.nodes, hole, u1, u2);
        }
    }
    if (rc == 0 && count) {
        r->t_root = sum / count;
        r->slid = s->puncture[0].s - s_start;
        r->linked = s->puncture[0].linked == 1;
        r->reference = coulomb_root_tension(mu, w_load, u1, u2);
    } else {
        rc = -1;
    }
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
    return rc;
}

static void test_pull(void)
{
    const double mu = 0.3, w_load = 0.05;
    /* 61 nodes, twice as fine from s = 32 mm on (1.47 mm before, 0.73 mm
     * after): the hole slides from 30 to 36 mm across the jump */
    pull_result g, u;
    if (!check(pull_through_pad("nodes = 61\nrefine = 0.032 0.06 2\n", mu, w_load, &g) == 0,
               "the pull through the pad's puncture runs on the graded grid"))
        return;
    check(g.linked, "graded: the hole is a point of the pad (linked)");
    check(g.slid > 0.0057 && g.slid < 0.0063, "graded: the thread slid %.5g m through the hole "
          "(the root pulled 0.006 m)", g.slid);
    check(g.moved > 1e-6, "graded: the pad moved the hole %.3g um under the thread's pull",
          1e6 * g.moved);
    check_rel("graded, mu = 0.3: root tension vs Coulomb's law at the hole where the pad holds "
              "it (N)", g.t_root, g.reference, 0.02);
    check(g.miss < 0.15 * 0.00015, "graded: the thread passes through the hole (largest miss "
          "%.3g m, limit 15 %% of the radius %.3g m)", g.miss, 0.00015);
    if (!check(pull_through_pad("nodes = 121\n", mu, w_load, &u) == 0,
               "the pull runs on a uniform grid of 121 nodes (0.5 mm)"))
        return;
    check_rel("uniform 121 nodes: root tension vs Coulomb's law (N)", u.t_root, u.reference, 0.02);
    check_rel("graded (61 nodes) against uniform (121 nodes): the root's tension (N)", g.t_root,
              u.t_root, 0.01);
    check_rel("graded against uniform: the hole's largest move with the pad (m)", g.moved,
              u.moved, 0.05);
}

/* ---- a needle through tissue ---- */

typedef struct bite {
    int ok, holes, tracks;
    double point[2][3]; /* m: the entry's and the exit's points */
    double s[2];        /* m: their arc lengths at the end */
    double deepest;     /* m: the thread's deepest point between them */
    double tip_ds;      /* m: the tip's segment */
} bite;

/* The bite of test_needle_bite.h (as test_needle_track.c's); `grid` the
 * [rod] lines nodes and refine. */
static bite run_bite(const char *grid, double spacing)
{
    bite o = {0};
    char path[512], text[2048], err[1024] = "";
    snprintf(path, sizeof path, "%s/back.csv", test_dir());
    if (bite_scene(path, grid, spacing, text, sizeof text)) return o;
    rod_model m;
    if (read_scene_text(text, &m, err, sizeof err)) {
        printf("     the bite's scene: %s\n", err);
        return o;
    }
    rod_solver solver;
    rod_state *s = run_start(&m, &solver);
    if (!s) {
        rod_model_release(&m);
        return o;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    const int steps = (int)lround((BITE_SWEEP + BITE_DRAW) / 0.001);
    o.ok = 1;
    for (int i = 1; i <= steps && o.ok; i++)
        if (rod_solver_step(&solver, &m, s, 0.001, &report) != ROD_OK) {
            printf("     bite step %d (t = %.3f s): %s\n", i, s->time, report.message);
            o.ok = 0;
        }
    o.tip_ds = rod_segment_ds(&m, m.nodes - 2);
    for (int k = 0; k < s->puncture_count; k++) {
        const rod_puncture_state *p = &s->puncture[k];
        if (p->track) {
            o.tracks++;
            continue;
        }
        if (o.holes < 2) {
            v3_copy(o.point[o.holes], p->point);
            o.s[o.holes] = p->s;
        }
        o.holes++;
    }
    for (int k = 0; k < m.nodes && o.holes == 2; k++) {
        const double sk = rod_node_arc(&m, k);
        if (sk > o.s[0] && sk < o.s[1]) o.deepest = fmax(o.deepest, -s->position[3 * k + 2]);
    }
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
    return o;
}

static void test_needle(void)
{
    /* 41 nodes, three times as fine over the last 15 mm (the needle's end):
     * 1.43 mm segments on the root's side, 0.48 mm at the needle; the
     * uniform grid 0.5 mm (81 nodes) */
    const char *graded = "nodes = 41\nrefine = 0.025 0.04 3\n";
    bite g = run_bite(graded, 0.0), u = run_bite("nodes = 81\n", 0.0);
    if (!check(g.ok && u.ok, "the needle's bite runs on the graded grid (41 nodes) and on a "
               "uniform one (81 nodes)"))
        return;
    if (!check(g.holes == 2 && u.holes == 2, "two holes each, the entry and the exit (graded %d, "
               "uniform %d)", g.holes, u.holes))
        return;
    printf("     the needle's segment: graded %.3g mm, uniform %.3g mm\n", 1e3 * g.tip_ds,
           1e3 * u.tip_ds);
    /* the circle meets the skin z = 0 at y = -+sqrt(R^2 - (R - D)^2); a hole
     * is cut where the thread crosses the skin once the needle's back is
     * about its segment past it (puncture_needle_holes), so within that
     * segment's length of the circle's crossing */
    const double zc = BITE_RADIUS - BITE_DEPTH;
    const double y_skin = sqrt(BITE_RADIUS * BITE_RADIUS - zc * zc);
    static const char *const name[2] = {"entry", "exit"};
    for (int h = 0; h < 2; h++) {
        char what[200];
        const double side = h == 0 ? -1.0 : 1.0;
        snprintf(what, sizeof what, "graded: the %s hole's y against the circle's crossing of "
                 "the skin (m; within the needle's segment)", name[h]);
        check_abs(what, g.point[h][1], side * y_skin, g.tip_ds);
        snprintf(what, sizeof what, "uniform: the %s hole's y against the same (m)", name[h]);
        check_abs(what, u.point[h][1], side * y_skin, u.tip_ds);
        double d[3];
        v3_sub(d, g.point[h], u.point[h]);
        snprintf(what, sizeof what, "graded against uniform: the %s hole's point, distance (m; "
                 "within a quarter of the thread's diameter)", name[h]);
        check_abs(what, v3_norm(d), 0.0, 0.25 * 0.00018);
        snprintf(what, sizeof what, "graded against uniform: the %s hole's arc length at the end "
                 "(m)", name[h]);
        check_rel(what, g.s[h], u.s[h], 0.01);
    }
    check_rel("graded against uniform: the thread between the holes (m)", g.s[1] - g.s[0],
              u.s[1] - u.s[0], 0.03);
    /* with the track (at least two of the longest segments apart) */
    bite t = run_bite(graded, 0.003);
    if (!check(t.ok, "the bite with the track runs on the graded grid")) return;
    check(t.holes == 2 && t.tracks >= 2, "graded, track_spacing 3 mm: %d holes (2) and %d track "
          "points (at least 2 along the 11 mm under the skin)", t.holes, t.tracks);
    check_rel("graded with the track: the thread's deepest point between the holes against the "
              "circle's depth (m)", t.deepest, BITE_DEPTH, 0.10);
}

/* ---- a puncture on a graded starting shape ---- */

/* A quarter circle of radius 20 mm given by 13 points, resampled to 41
 * nodes three times as fine over its first half; a [puncture] 20 um beside
 * the shape's middle point, off the resampled thread by more than the
 * slack a puncture is taken in as it is (1 % of ds): it is
 * moved onto the thread at its arc length (s_j + alpha ds_j), so it lies on
 * the thread where the shape's point is, at half the polyline's length. */
static void test_shape_puncture(void)
{
    /* the polyline's length: 12 chords of 2 R sin(pi / 48) */
    const double radius = 0.02, length = 24.0 * radius * sin(M_PI / 48.0);
    char path[512], text[2048], err[1024] = "";
    snprintf(path, sizeof path, "%s/arc.csv", test_dir());
    FILE *f = fopen(path, "w");
    if (!f) return;
    fprintf(f, "x,y,z\n");
    double mid[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k <= 12; k++) {
        const double a = 0.5 * M_PI * k / 12.0;
        const double p[3] = {radius * sin(a), 0.0, radius * (1.0 - cos(a))};
        fprintf(f, "%.12f,%.12f,%.12f\n", p[0], p[1], p[2]);
        if (k == 6) v3_copy(mid, p);
    }
    fclose(f);
    mid[1] = 2e-5; /* 20 um aside: more than the slack a puncture is taken in as it is */
    snprintf(text, sizeof text,
             "[rod]\nlength = %.12f\ndiameter = 0.0003\ndensity = 1140\nyoungs_modulus = 1e9\n"
             "shear_modulus = 0.37e9\nnodes = 41\nrefine = 0 %.12f 3\nshape = %s\n"
             "self_contact = no\n[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.01\n"
             "[puncture]\npoint = %.12f %.12f %.12f\n",
             length, 0.5 * length, path, mid[0], mid[1], mid[2]);
    rod_model m;
    if (!check(read_scene_text(text, &m, err, sizeof err) == 0, "the graded arc with a puncture "
               "reads (%s)", err))
        return;
    rod_state *s = rod_state_create(&m);
    if (s) {
        double distance, moved[3];
        const double along =
            rod_nearest_arc_length(&m, s->position, m.punctures[0].point, &distance);
        v3_sub(moved, m.punctures[0].point, mid);
        check(strstr(m.adjusted, "[puncture] 1 moved") != NULL, "the puncture was off the "
              "resampled thread and was moved (%s)", m.adjusted);
        check_abs("the moved puncture's distance from the graded thread (m)", distance, 0.0, 1e-12);
        check_abs("the moved puncture's distance from where it was given (m; within its 20 um "
                  "aside and the shape's stray from the resampled thread)", v3_norm(moved), 0.0,
                  2e-5 + m.shape_moved);
        check_rel("the moved puncture's arc length against the shape's middle point's (m)", along,
                  0.5 * length, 0.01);
    }
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* ---- the command line ---- */

static void test_scenes(void)
{
    const char *dir = test_dir();
    char out_dir[512], scene[512];
    static char output[1 << 16];
    snprintf(out_dir, sizeof out_dir, "%s/out", dir);
#define GRADED_ROD "[rod]\nlength = 0.024\ndiameter = 0.002\ndensity = 7800\n" \
                   "youngs_modulus = 2e11\nshear_modulus = 8e10\nnodes = 25\n" \
                   "refine = 0.008 0.016 3\norigin = -0.012 0.002 0.0012\n" \
                   "[ends]\nroot = free\ntip = free\n[loads]\ngravity = 0 0 -9.81\n" \
                   "linear_damping = 3\n[solver]\ndt = 0.001\nduration = 0.02\n"
    test_write_in(dir, "pad.ini", GRADED_ROD "[surface]\nshape = box\ncenter = 0 0 -0.004\n"
                  "size = 0.04 0.03 0.008\ntissue = yes\nmodel = elastic\n"
                  "youngs_modulus = 2e3\nelement_size = 0.004\n");
    test_write_in(dir, "tissue.ini", GRADED_ROD "[surface]\nshape = plane\ncenter = 0 0 0\n"
                  "tissue = yes\n");
    test_write_in(dir, "jaws.csv", "t,x,y,z,rx,ry,rz,jaw\n0,0,0,0.05,0,0,0,1\n"
                  "0.02,0,0,0.05,0,0,0,1\n");
    test_write_in(dir, "scissors.ini", GRADED_ROD "[surface]\nshape = plane\ncenter = 0 0 0\n"
                  "tissue = yes\n[instrument]\nkind = scissors\npath = jaws.csv\n");
    static const char *const names[2] = {"pad.ini", "tissue.ini"};
    static const char *const what[2] = {"an elastic pad", "a rigid tissue surface"};
    for (int k = 0; k < 2; k++) {
        snprintf(scene, sizeof scene, "%s/%s", dir, names[k]);
        const char *args[] = {"run", scene, "-o", out_dir, "--no-video", NULL};
        const int status = test_run_rodsim(args, output, sizeof output);
        check(status == 0, "rodsim run of a graded scene with %s: exit %d (0)%s%.300s", what[k],
              status, status ? ": " : "", status ? output : "");
    }
    snprintf(scene, sizeof scene, "%s/scissors.ini", dir);
    const char *args[] = {"run", scene, "-o", out_dir, "--no-video", NULL};
    const int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "rodsim run of a graded scene with tissue and scissors: exit %d (0)%s%.300s",
          status, status ? ": " : "", status ? output : "");
}

int main(void)
{
    test_wire_on_pad();
    test_pull();
    test_needle();
    test_shape_puncture();
    test_scenes();
    return test_finish();
}
