/* test_grid_follow.c: a suture drawn 25 mm through two holes on a graded
 * grid (scene [rod] refine, sim/rod_grid.h) whose fine stretch must follow
 * the material in the holes (docs/decisions/0159-grid-follow.md):
 *   - stitch.ini's thread (0.18 mm nylon, E = 1.5 GPa, EI = 7.7e-8 N m^2,
 *     record 0139's sqrt(EI / T) = 0.16 mm at 3 N), two [puncture]s 4 mm
 *     apart (entry A, exit B), the thread turning 113 degrees into each
 *     (record 0139's turn), a load W on the needle's end, the tail's end
 *     drawn 25 mm along its strand in 2.6 s (stitch.ini's pull-through);
 *     sqrt(EI / T) = 0.12 .. 0.23 mm at the holes;
 *   - (a) a graded grid fine (0.1 mm) over every arc length that passes
 *     through a hole during the draw (grid_follow_intervals), (b) a graded
 *     grid fine within 1 mm of each hole's material, regridded as it slides
 *     (regrid: a prototype); with `bench`, also uniform grids at 1 mm
 *     (stitch.ini's spacing; it stops) and 0.1 mm and (b) at 0.05 and
 *     0.025 mm;
 *   - each run's root tension over the draw against Coulomb's law at each
 *     puncture chained from W, with the strands' directions of every step,
 *     the friction along the thread's own tangent at the hole where the
 *     grid resolves the bend (coulomb_in_resolved); printed beside the same
 *     law on the strands' bisector and the capstan's W exp(mu (theta_A +
 *     theta_B)); (b) against (a); a regrid's state against the scheme's
 *     (chords along the frames) and the centreline it was on; nodes, Newton
 *     iterations a step and CPU seconds per simulated second printed (not
 *     asserted). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/clocks.h"
#include "base/vec3.h"
#include "sim/contact/puncture.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/rod_geometry.h"
#include "sim/rod_grid.h"
#include "test.h"
#include "test_puncture_pull.h"
#include "test_run_start.h"

#define LENGTH 0.055     /* m */
#define BITE 0.004       /* m: entry to exit */
#define ROOT_STRAND 0.008/* m: the starting shape's straight tail */
#define FILLET 0.002     /* m: the starting shape's radius into each hole */
#define TURN (113.0 * M_PI / 180.0)
#define DRAW 0.025       /* m */
#define T_LOAD 0.3       /* s: W ramped, the loops drawn in, before the draw */
#define T_DRAW 2.6       /* s */
#define T_END (T_LOAD + T_DRAW + 0.1)
#define MU 0.2           /* puncture.friction's default */
#define W_LOAD 1.5       /* N */
#define DT 1e-3          /* s, stitch.ini's */

/* The strands' directions away from the holes: the tail's from A rising
 * back over the bite, the needle's end from B likewise, each turning TURN
 * into the bite (A to B along +x), aside in y so they do not cross. */
static void start_directions(double u1[3], double u2[3])
{
    const double c = -cos(TURN), y = 0.3, z = sqrt(1.0 - c * c - y * y);
    v3_set(u1, c, -y, z);
    v3_set(u2, -c, y, z);
}

/* The starting centreline sampled every `h` m from the root: the tail
 * straight along -u1, an arc of radius FILLET turning to +x that ends at A
 * (the origin), A to B, an arc turning to u2 from B, then straight. Returns
 * the points written (at most cap). */
static int centreline(double h, double *p, int cap)
{
    double u1[3], u2[3], a[3], x[3] = {1, 0, 0}, k[3], c[3], t[3], kt[3];
    start_directions(u1, u2);
    v3_scale(a, u1, -1.0);
    const double arc = FILLET * TURN, total = LENGTH + 0.01;
    int n = 0;
    for (double s = 0.0; s <= total && n < cap; s += h, n++) {
        double *q = &p[3 * n];
        if (s < ROOT_STRAND + arc) {
            /* arc A: t(phi) = rot(k, phi) a, P = C - R k x t, C = A + R k x x */
            v3_cross(k, a, x);
            v3_scale(k, k, 1.0 / v3_norm(k));
            v3_cross(kt, k, x);
            v3_scale(c, kt, FILLET);
            double phi = (s - ROOT_STRAND) / FILLET, r[3];
            if (phi < 0.0) {
                /* on the straight tail before the arc */
                v3_cross(kt, k, a);
                v3_axpy(c, -FILLET, kt);
                v3_copy(q, c);
                v3_axpy(q, phi * FILLET, a);
                continue;
            }
            v3_scale(r, k, phi);
            v3_rotate(t, r, a);
            v3_cross(kt, k, t);
            v3_copy(q, c);
            v3_axpy(q, -FILLET, kt);
        } else if (s < ROOT_STRAND + arc + BITE) {
            v3_set(q, s - ROOT_STRAND - arc, 0.0, 0.0);
        } else {
            const double sb = s - ROOT_STRAND - arc - BITE, b[3] = {BITE, 0, 0};
            v3_cross(k, x, u2);
            v3_scale(k, k, 1.0 / v3_norm(k));
            v3_cross(kt, k, x);
            v3_copy(c, b);
            v3_axpy(c, FILLET, kt);
            const double phi = fmin(sb / FILLET, TURN);
            double r[3];
            v3_scale(r, k, phi);
            v3_rotate(t, r, x);
            v3_cross(kt, k, t);
            v3_copy(q, c);
            v3_axpy(q, -FILLET, kt);
            if (sb > arc) v3_axpy(q, sb - arc, u2);
        }
    }
    return n;
}

/* The model's initial_shape: nodes at chords ds_j along the sampled
 * centreline (check_shape wants every segment its rest length). */
static int place_nodes(rod_model *m)
{
    const double h = 1e-6;
    const int cap = (int)((LENGTH + 0.011) / h);
    double *p = malloc((size_t)cap * 3 * sizeof(double));
    m->initial_shape = malloc((size_t)m->nodes * 3 * sizeof(double));
    if (!p || !m->initial_shape) {
        free(p);
        return -1;
    }
    const int n = centreline(h, p, cap);
    v3_copy(m->initial_shape, p);
    int q = 0;
    for (int i = 0; i + 1 < m->nodes; i++) {
        const double *a = &m->initial_shape[3 * i], ds = rod_segment_ds(m, i);
        double d[3];
        for (;;) {
            if (q + 1 >= n) {
                free(p);
                return -1;
            }
            v3_sub(d, &p[3 * (q + 1)], a);
            if (v3_norm(d) >= ds) break;
            q++;
        }
        /* |p_q + f (p_q+1 - p_q) - a| = ds on that sample segment */
        double e[3], w[3];
        v3_sub(e, &p[3 * (q + 1)], &p[3 * q]);
        v3_sub(w, &p[3 * q], a);
        const double aa = v3_dot(e, e), bb = 2.0 * v3_dot(e, w), cc = v3_dot(w, w) - ds * ds;
        const double f = (-bb + sqrt(bb * bb - 4.0 * aa * cc)) / (2.0 * aa);
        double *b = &m->initial_shape[3 * (i + 1)];
        v3_copy(b, &p[3 * q]);
        v3_axpy(b, f, e);
    }
    free(p);
    return 0;
}

/* Arc lengths (m) of the material in A and B on the starting shape. */
static void starting_hole_arcs(double *sa, double *sb)
{
    *sa = ROOT_STRAND + FILLET * TURN;
    *sb = *sa + BITE;
}

/* The rule (a): one fine interval covering every arc length that is in a
 * hole at some time of a draw of `drawn` m toward the root: from entry's
 * starting arc length less `margin` to exit's plus the draw and `margin`
 * (the holes' sweeps [s_A, s_A + drawn] and [s_B, s_B + drawn] overlap when
 * the bite is shorter than the draw; else two intervals). Returns the count. */
static int grid_follow_intervals(double s_entry, double s_exit, double drawn, double margin,
                                 double factor, double length, rod_refine *out)
{
    double lo[2] = {s_entry - margin, s_exit - margin};
    double hi[2] = {s_entry + drawn + margin, s_exit + drawn + margin};
    if (drawn < 0.0) {
        lo[0] = s_entry + drawn - margin, lo[1] = s_exit + drawn - margin;
        hi[0] = s_entry + margin, hi[1] = s_exit + margin;
    }
    int n = 0;
    for (int k = 0; k < 2; k++) {
        const double a = fmax(0.0, lo[k]), b = fmin(length, hi[k]);
        if (n && a <= out[n - 1].s1) {
            out[n - 1].s1 = fmax(out[n - 1].s1, b);
            continue;
        }
        out[n++] = (rod_refine){a, b, factor};
    }
    return n;
}

/* The node count whose segments outside the fine intervals are `coarse` m. */
static int nodes_for(const rod_refine *r, int count, double coarse)
{
    double stretched = LENGTH;
    for (int k = 0; k < count; k++) stretched += (r[k].factor - 1.0) * (r[k].s1 - r[k].s0);
    return 1 + (int)lround(stretched / coarse);
}

/* The root tension Coulomb's law gives at a puncture whose strands leave it
 * along u1 (the puller's side, tension T1) and u2 (tension t2). */
static double coulomb_in(double t2, const double u1[3], const double u2[3])
{
    return coulomb_tension_up_to(MU, t2, u1, u2, 50.0);
}

/* The same law where the grid resolves the bend (ds below sqrt(EI / T)):
 * the puncture's friction is along the thread's own tangent at the hole,
 * which is not the strands' bisector when their tensions differ. The
 * elastica on each side, under T1 and t2, turns by a1 and a2 = theta - a1
 * (theta the strands' turn, from -u1 to u2) with the curvature continuous
 * at the hole (no point moment): T1 (1 - cos a1) = t2 (1 - cos a2), and
 * sliding: T1 cos a1 - t2 cos a2 = mu (T1 sin a1 + t2 sin a2). Bisection on
 * a1 in (0, theta / 2). */
static double coulomb_in_resolved(double t2, const double u1[3], const double u2[3])
{
    const double theta = acos(fmax(-1.0, fmin(1.0, -v3_dot(u1, u2))));
    double lo = 1e-9, hi = 0.5 * theta, t1 = t2;
    for (int it = 0; it < 200; it++) {
        const double a1 = 0.5 * (lo + hi), a2 = theta - a1;
        t1 = t2 * (1.0 - cos(a2)) / (1.0 - cos(a1));
        const double g = t1 * cos(a1) - t2 * cos(a2) - MU * (t1 * sin(a1) + t2 * sin(a2));
        if (g > 0.0) lo = a1;
        else hi = a1;
    }
    return t1;
}

/* A regrid (the prototype of (b)): the refine intervals `r` (count) for the
 * model whose state is `s`: frames along the geodesic between the old
 * neighbours at each new node's arc length, the centreline rebuilt from
 * them from the root (every segment its rest length, as the scheme keeps
 * it); global velocities interpolated linearly in arc length,
 * angular velocities and staggered values in their components; punctures
 * keep their arc lengths. The solver is made again by the caller. */
static int regrid(rod_model *m, rod_state *s, const rod_refine *r, int count, double *moved)
{
    const int n = m->nodes;
    double *old_arc = malloc((size_t)n * sizeof(double));
    double *pos = malloc((size_t)n * 3 * sizeof(double));
    double *frame = malloc((size_t)n * 9 * sizeof(double));
    double *vel = malloc((size_t)n * 3 * sizeof(double));
    double *omega = malloc((size_t)n * 3 * sizeof(double));
    double *cf = malloc((size_t)n * 3 * sizeof(double));
    if (!old_arc || !pos || !frame || !vel || !omega || !cf) {
        free(old_arc), free(pos), free(frame), free(vel), free(omega), free(cf);
        return -1;
    }
    old_arc[0] = 0.0;
    for (int i = 1; i < n; i++) old_arc[i] = old_arc[i - 1] + m->segment_length[i - 1];
    /* old midpoints' arc lengths, for the staggered contact force */
    double *old_seg = malloc((size_t)(n - 1) * sizeof(double));
    if (!old_seg) {
        free(old_arc), free(pos), free(frame), free(vel), free(omega), free(cf);
        return -1;
    }
    memcpy(old_seg, m->segment_length, (size_t)(n - 1) * sizeof(double));
    m->refine_count = count;
    for (int k = 0; k < count; k++) m->refine[k] = r[k];
    rod_grid_segment_lengths(m, m->segment_length);
    double arc = 0.0;
    int j = 0;
    for (int i = 0; i < n; i++) {
        if (i) arc += m->segment_length[i - 1];
        if (i == n - 1) arc = old_arc[n - 1];
        while (j + 2 < n && old_arc[j + 1] <= arc) j++;
        const double a = (arc - old_arc[j]) / old_seg[j];
        const double *qa = &s->frame[9 * j], *qb = &s->frame[9 * (j + 1)];
        double rel[9], phi[3], turn[9], va[3], vb[3];
        for (int c = 0; c < 3; c++)
            pos[3 * i + c] = (1.0 - a) * s->position[3 * j + c] + a * s->position[3 * (j + 1) + c];
        m3_mul_tn(rel, qa, qb);
        m3_log(phi, rel);
        v3_scale(phi, phi, a);
        m3_exp(turn, phi);
        m3_mul(&frame[9 * i], qa, turn);
        m3_mul_v(va, qa, &s->velocity[3 * j]);
        m3_mul_v(vb, qb, &s->velocity[3 * (j + 1)]);
        double v[3];
        for (int c = 0; c < 3; c++) v[c] = (1.0 - a) * va[c] + a * vb[c];
        m3_mul_tv(&vel[3 * i], &frame[9 * i], v);
        for (int c = 0; c < 3; c++) {
            omega[3 * i + c] = (1.0 - a) * s->angular_velocity[3 * j + c] +
                               a * s->angular_velocity[3 * (j + 1) + c];
        }
    }
    /* staggered contact force: at the new midpoints from the old ones' */
    arc = 0.0;
    double mid_old = 0.5 * old_seg[0];
    j = 0;
    for (int i = 0; i + 1 < n; i++) {
        const double mid = arc + 0.5 * m->segment_length[i];
        arc += m->segment_length[i];
        while (j + 2 < n - 1 && old_arc[j + 1] + 0.5 * old_seg[j + 1] <= mid) j++;
        mid_old = old_arc[j] + 0.5 * old_seg[j];
        const double next = old_arc[j + 1] + 0.5 * old_seg[j + 1];
        const double a = fmin(1.0, fmax(0.0, (mid - mid_old) / (next - mid_old)));
        for (int c = 0; c < 3; c++)
            cf[3 * i + c] = (1.0 - a) * s->contact_force[3 * j + c] +
                            a * s->contact_force[3 * (j + 1) + c];
    }
    v3_copy(&cf[3 * (n - 1)], &s->contact_force[3 * (n - 1)]);
    /* the centreline from the frames' d3 at the new midpoints (3.12), from
     * the root: the scheme's own, every segment its rest length, no shear */
    memcpy(s->frame, frame, (size_t)n * 9 * sizeof(double));
    rod_darboux_from_frames(m, s->frame, s->darboux);
    double *mid = malloc((size_t)n * 9 * sizeof(double)), root[3];
    if (!mid) {
        free(old_arc), free(pos), free(frame), free(vel), free(omega), free(cf), free(old_seg);
        return -1;
    }
    rod_midpoint_frames(m, s->frame, s->darboux, mid);
    v3_copy(root, s->position);
    rod_positions_from_midframes(m, mid, s->position);
    free(mid);
    for (int i = 0; i < n; i++) {
        double d[3];
        v3_add(&s->position[3 * i], &s->position[3 * i], root);
        v3_sub(d, &s->position[3 * i], &pos[3 * i]);
        *moved = fmax(*moved, v3_norm(d));
    }
    memcpy(s->velocity, vel, (size_t)n * 3 * sizeof(double));
    memcpy(s->angular_velocity, omega, (size_t)n * 3 * sizeof(double));
    memcpy(s->contact_force, cf, (size_t)n * 3 * sizeof(double));
    rod_darboux_from_frames(m, s->frame, s->darboux);
    v3_copy(&s->darboux[3 * (n - 1)], &s->darboux[3 * (n - 2)]);
    free(old_arc), free(pos), free(frame), free(vel), free(omega), free(cf), free(old_seg);
    return 0;
}

/* The largest angle between a segment's chord and its midpoint frame's d3
 * (the shear the state carries), rad. */
static double worst_shear(const rod_model *m, const rod_state *s)
{
    const int n = m->nodes;
    double *u = malloc((size_t)n * 3 * sizeof(double));
    double *mid = malloc((size_t)n * 9 * sizeof(double));
    double worst = 0.0;
    if (u && mid) {
        rod_darboux_from_frames(m, s->frame, u);
        rod_midpoint_frames(m, s->frame, u, mid);
        for (int j = 0; j + 1 < n; j++) {
            double c[3], d3[3];
            v3_sub(c, &s->position[3 * (j + 1)], &s->position[3 * j]);
            m3_column(d3, &mid[9 * j], 2);
            worst = fmax(worst, acos(fmin(1.0, v3_dot(c, d3) / v3_norm(c))));
        }
    }
    free(u);
    free(mid);
    return worst;
}

typedef struct follow_result {
    int nodes;
    int ok;              /* 1: ran to the end */
    double stopped_at;   /* s: where it stopped, when not */
    double cpu;          /* s CPU for the whole run */
    double newton;       /* Newton iterations a step */
    double t_root;       /* N: mean root tension over the draw's middle */
    double t_law;        /* N: mean of Coulomb's chained law there */
    double t_bisector;   /* N: the same with the friction along the strands' bisector */
    double t_capstan;    /* N: mean of W exp(mu (theta_A + theta_B)) there */
    double slid;         /* m: the puncture at A's arc length's change */
    double worst_bend;   /* rad: the largest turn between neighbouring frames */
    double worst_bend_t, worst_bend_s; /* s, m: when and where (the segment's midpoint) */
    double jump;         /* largest step-to-step change of the root tension over its mean */
    int regrids;
    double shear_before; /* rad: worst_shear just before a regrid, the largest */
    double shear_after;  /* rad: the same just after one */
    double moved;        /* m: the largest distance of a node rebuilt from the frames from
                            the old centreline's point at its arc length, over the regrids */
} follow_result;

/* One run: `refine` (count; 0 uniform) at `nodes`; follow_window > 0: the
 * prototype (b), fine intervals of half-width follow_window about each
 * hole's material, moved when a hole is more than half of it off centre. */
static int follow(int nodes, const rod_refine *refine, int count, double follow_window,
                  double factor, follow_result *r)
{
    memset(r, 0, sizeof *r);
    r->nodes = nodes;
    rod_model m = rod_model_default();
    m.length = LENGTH;
    m.diameter = 0.00018;
    m.density = 1140;
    m.youngs_modulus = 1.5e9;
    m.shear_modulus = 0.55e9;
    m.nodes = nodes;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.self_contact = 0;
    m.root_end = ROD_END_PINNED;
    m.tip_end = ROD_END_FREE;
    m.linear_damping = 2e-3;
    m.refine_count = count;
    for (int k = 0; k < count; k++) m.refine[k] = refine[k];
    double u1[3], u2[3];
    start_directions(u1, u2);
    m.tip_frame = ROD_FRAME_GLOBAL;
    v3_scale(m.tip_force, u2, W_LOAD);
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 0.2;
    rod_puncture holes[2] = {{{0.0, 0.0, 0.0}, MU, 0}, {{BITE, 0.0, 0.0}, MU, 1}};
    m.puncture_count = 2;
    m.punctures = holes;
    char err[512];
    int rc = -1;
    rod_state *s = NULL;
    /* the grid first (initial_shape is placed on it), then the model */
    if (count) {
        m.segment_length = malloc((size_t)(nodes - 1) * sizeof(double));
        if (!m.segment_length) goto done;
        m.ds = LENGTH / (nodes - 1);
        rod_grid_segment_lengths(&m, m.segment_length);
    } else {
        m.ds = LENGTH / (nodes - 1);
    }
    if (place_nodes(&m)) goto done;
    const double *r0 = m.initial_shape;
    const double rows[12] = {0.0,    r0[0], r0[1], r0[2], T_LOAD, r0[0], r0[1], r0[2],
                             T_LOAD + T_DRAW, r0[0] + DRAW * u1[0], r0[1] + DRAW * u1[1],
                             r0[2] + DRAW * u1[2]};
    m.root_motion = rod_path_create(rows, 3, 4, err, sizeof err);
    if (!m.root_motion) goto done;
    if (rod_model_derive(&m, err, sizeof err)) {
        printf("     derive: %s\n", err);
        goto done;
    }
    rod_solver solver;
    s = run_start(&m, &solver);
    if (!s) goto done;
    rod_report report;
    memset(&report, 0, sizeof report);
    const int steps = (int)lround(T_END / DT);
    const double s_a0 = s->puncture[0].s;
    double sum = 0.0, law = 0.0, bis = 0.0, cap = 0.0, last_t = NAN, jump = 0.0, centre[2];
    int samples = 0;
    long newton = 0;
    centre[0] = s->puncture[0].s, centre[1] = s->puncture[1].s;
    const double cpu0 = cpu_seconds();
    rc = 0;
    for (int k = 1; k <= steps; k++) {
        if (rod_solver_step(&solver, &m, s, DT, &report)) {
            printf("     step %d (t = %g s): %s\n", k, s->time, report.message);
            r->stopped_at = s->time;
            newton += report.newton_total;
            rc = -1;
            break;
        }
        int seg;
        rod_darboux_from_frames(&m, s->frame, s->darboux);
        const double bend = rod_sharpest_bend(&m, s->darboux, &seg);
        if (bend > r->worst_bend) {
            r->worst_bend = bend;
            r->worst_bend_t = s->time;
            r->worst_bend_s = rod_node_arc(&m, seg) + 0.5 * rod_segment_ds(&m, seg);
        }
        if (follow_window > 0.0) {
            const double sa = s->puncture[0].s, sb = s->puncture[1].s;
            if (fabs(sa - centre[0]) > 0.5 * follow_window ||
                fabs(sb - centre[1]) > 0.5 * follow_window) {
                /* centred ahead of the slide: the material coming in */
                centre[0] = sa + 0.25 * follow_window, centre[1] = sb + 0.25 * follow_window;
                rod_refine w[2] = {{centre[0] - follow_window, centre[0] + follow_window, factor},
                                   {centre[1] - follow_window, centre[1] + follow_window, factor}};
                int wc = 2;
                if (w[0].s1 >= w[1].s0) w[0].s1 = w[1].s1, wc = 1;
                newton += report.newton_total;
                rod_solver_release(&solver);
                r->shear_before = fmax(r->shear_before, worst_shear(&m, s));
                if (regrid(&m, s, w, wc, &r->moved) ||
                    rod_solver_init(&solver, &m, err, sizeof err)) {
                    printf("     regrid: %s\n", err);
                    rc = -1;
                    break;
                }
                memset(&report, 0, sizeof report);
                r->shear_after = fmax(r->shear_after, worst_shear(&m, s));
                r->regrids++;
            }
        }
        /* the draw's middle: 40 % to 90 % of it */
        const double t = s->time;
        if (t > T_LOAD + 0.4 * T_DRAW && t < T_LOAD + 0.9 * T_DRAW) {
            double a1[3], a2[3], b1[3], b2[3];
            const double *A = holes[0].point, *B = holes[1].point;
            v3_sub(a1, &s->position[0], A);
            v3_scale(a1, a1, 1.0 / v3_norm(a1));
            v3_sub(a2, B, A);
            v3_scale(a2, a2, 1.0 / v3_norm(a2));
            v3_scale(b1, a2, -1.0);
            v3_sub(b2, &s->position[3 * (m.nodes - 1)], B);
            v3_scale(b2, b2, 1.0 / v3_norm(b2));
            const double t_mid = coulomb_in_resolved(W_LOAD, b1, b2),
                         t_a = coulomb_in_resolved(t_mid, a1, a2),
                         t_bis = coulomb_in(coulomb_in(W_LOAD, b1, b2), a1, a2);
            const double ta = acos(-v3_dot(a1, a2)), tb = acos(-v3_dot(b1, b2));
            const double tr = v3_norm(s->end_force[0]);
            sum += tr, law += t_a, bis += t_bis, cap += W_LOAD * exp(MU * (ta + tb));
            if (isfinite(last_t)) jump = fmax(jump, fabs(tr - last_t));
            last_t = tr;
            samples++;
        }
    }
    r->cpu = cpu_seconds() - cpu0;
    if (rc == 0) newton += report.newton_total;
    r->newton = (double)newton / (s->time / DT);
    r->slid = s->puncture[0].s - s_a0;
    if (rc == 0 && samples) {
        r->ok = 1;
        r->t_root = sum / samples;
        r->t_law = law / samples;
        r->t_capstan = cap / samples;
        r->t_bisector = bis / samples;
        r->jump = jump / r->t_root;
    }
    rod_solver_release(&solver);
done:
    rod_state_destroy(s);
    m.punctures = NULL;
    m.puncture_count = 0;
    rod_model_release(&m);
    return r->ok ? 0 : -1;
}

static void print_result(const char *name, const follow_result *r)
{
    printf("     %-34s nodes %4d  %s  CPU %.2f s / simulated s  Newton %.2f a step  "
           "largest turn %.3f rad (t = %.3f s, s = %.2f mm)", name, r->nodes,
           r->ok ? "ran" : "stopped", r->cpu / (r->ok ? T_END : fmax(r->stopped_at, DT)),
           r->newton, r->worst_bend, r->worst_bend_t, 1e3 * r->worst_bend_s);
    if (r->ok)
        printf("  root %.5g N, law %.5g N (%+.2e), bisector's %.5g N, capstan %.5g N, "
               "slid %.2f mm, tension's largest step %.2e, regrids %d (shear %.2e rad before, "
               "%.2e after; nodes moved %.2e m)", r->t_root, r->t_law,
               r->t_root / r->t_law - 1.0, r->t_bisector, r->t_capstan, 1e3 * r->slid, r->jump,
               r->regrids, r->shear_before, r->shear_after, r->moved);
    else
        printf("  at t = %.3f s", r->stopped_at);
    printf("\n");
}

/* The law's tolerance: the law is quasi-static and the draw is at the
 * stitch's speed; the root's tension sits 4.4-4.8 % over the law on every
 * grid fine at the holes (0.1 mm: uniform, graded over the slide,
 * regridded) and moves with the speed ((b) drawn in 7.8 s: -1.7 %, in
 * 1.3 s: +9.2 %), its scatter step to step 60-80 % of its mean at 0.1 mm
 * (the hole crossing nodes) averaged over the draw. */
#define LAW_TOLERANCE 0.06

int main(int argc, char **argv)
{
    const int bench = argc > 1 && strcmp(argv[1], "bench") == 0;
    double sa, sb;
    starting_hole_arcs(&sa, &sb);
    const double coarse = 0.001, factor = 10.0, window = 0.001;
    rod_refine a[2];
    const int ac = grid_follow_intervals(sa, sb, DRAW, 0.0015, factor, LENGTH, a);
    check(ac == 1 && fabs(a[0].s0 - (sa - 0.0015)) < 1e-12 &&
          fabs(a[0].s1 - (sb + DRAW + 0.0015)) < 1e-12,
          "(a): one interval %.4g .. %.4g m (the holes at %.4g and %.4g m, drawn %.3g m)",
          a[0].s0, a[0].s1, sa, sb, DRAW);
    follow_result ra, rb, rf, rc;
    const int na = nodes_for(a, ac, coarse);
    const int a_ok = follow(na, a, ac, 0.0, factor, &ra) == 0;
    print_result("graded (a): fine over the slide", &ra);
    check(a_ok, "the draw runs on the graded grid fine over the slide (%d nodes)", na);
    if (a_ok) {
        check(ra.slid > 0.9 * DRAW && ra.slid < 1.05 * DRAW,
              "(a): the thread slid %.4g m through the entry (the root drawn %.3g m)", ra.slid,
              DRAW);
        check_rel("(a): root tension over the draw vs Coulomb's law at both punctures, "
                  "the bend resolved (N)", ra.t_root, ra.t_law, LAW_TOLERANCE);
        check(fabs(ra.t_root / ra.t_bisector - 1.0) > 0.2,
              "(a): the friction is along the thread's own tangent, not the strands' bisector: "
              "root %.4g N against the bisector's law %.4g N", ra.t_root, ra.t_bisector);
    }
    rod_refine w[2] = {{sa - window, sa + window, factor}, {sb - window, sb + window, factor}};
    const int nb = nodes_for(w, 2, coarse);
    const int b_ok = follow(nb, w, 2, window, factor, &rb) == 0;
    print_result("graded (b): regridded, +-1 mm", &rb);
    check(b_ok && rb.regrids >= 30, "the draw runs on a grid fine within 1 mm of each hole, "
          "regridded as they slide (%d nodes, %d regrids)", nb, rb.regrids);
    if (b_ok && a_ok) {
        check(rb.slid > 0.9 * DRAW && rb.slid < 1.05 * DRAW,
              "(b): the thread slid %.4g m through the entry", rb.slid);
        check_rel("(b): root tension vs Coulomb's law, the bend resolved (N)", rb.t_root,
                  rb.t_law, LAW_TOLERANCE);
        check_rel("(b) against (a): root tension over the draw (N)", rb.t_root, ra.t_root, 0.01);
        check(rb.shear_after < 1e-6 && rb.moved < 0.5 * 0.00018,
              "(b): a regrid leaves the state the scheme's own (chords along the midpoint "
              "frames' d3: %.2e rad off, before it %.2e rad) and the nodes within %.3g m of the "
              "centreline they were on (limit the thread's radius %.3g m)", rb.shear_after,
              rb.shear_before, rb.moved, 0.5 * 0.00018);
        check(rb.jump <= 1.2 * ra.jump, "(b): the root tension's largest change in a step, "
              "regrids included, %.3g of its mean, against (a)'s %.3g (its node crossings)",
              rb.jump, ra.jump);
    }
    if (bench) {
        const int nc = (int)lround(LENGTH / coarse) + 1;
        const int nf = (int)lround(LENGTH / (coarse / factor)) + 1;
        follow(nc, NULL, 0, 0.0, factor, &rc);
        print_result("uniform 1 mm", &rc);
        follow(nf, NULL, 0, 0.0, factor, &rf);
        print_result("uniform 0.1 mm", &rf);
        /* the node count the 1 mm run's message asks for */
        follow(185, NULL, 0, 0.0, factor, &rf);
        print_result("uniform 185 nodes (0.3 mm)", &rf);
        const double finer[2] = {20.0, 40.0};
        for (int q = 0; q < 2; q++) {
            rod_refine v[2] = {{sa - window, sa + window, finer[q]},
                               {sb - window, sb + window, finer[q]}};
            char name[64];
            snprintf(name, sizeof name, "graded (b), %.3g mm in", 1e3 * coarse / finer[q]);
            follow(nodes_for(v, 2, coarse), v, 2, window, finer[q], &rb);
            print_result(name, &rb);
        }
    }
    return test_finish();
}
