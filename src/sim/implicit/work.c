/* work.c: the implicit scheme's work, made and freed (work.h). */
#include "sim/implicit/work.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/rod.h"
#include "sim/rod_geometry.h"

void implicit_destroy(implicit_work *w)
{
    if (!w) return;
    double **arrays[] = {&w->x, &w->dx, &w->x_last, &w->x_before, &w->x_before2, &w->residual,
                         &w->eval_x, &w->perturbed, &w->frame0, &w->omega0, &w->vel0, &w->vel1,
                         &w->d3mid0, &w->moment0, &w->tipf0, &w->tipm0, &w->frame1,
                         &w->frame_th, &w->darboux1, &w->mid1, &w->d3mid1, &w->moment1,
                         &w->save_frame, &w->save_pos, &w->save_vel, &w->save_omega,
                         &w->save_force, &w->phi0, &w->phi1, &w->phi_th, &w->point_force,
                         &w->point_moment, &w->vbar, &w->pos0, &w->band_smooth, &w->trail_jac,
                         &w->jac_node, &w->jac_seg};
    for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; k++) free(*arrays[k]);
    free(w->node_push);
    rod_self_contact_destroy(w->self);
    rod_contact_destroy(&w->contact);
    band_lu_destroy(&w->lu);
    free(w->trail_touched);
    free(w);
}

static const char *const end_names[2] = {"root", "tip"};

/* Reads one end's condition; -1 with a message when the scheme cannot model it. */
static int read_end(end_condition *e, int which, rod_end_kind kind, const double slide[3],
                    int twist_held, const rod_path *path, char *err, size_t errlen)
{
    memset(e, 0, sizeof *e);
    double len = v3_norm(slide);
    if (kind == ROD_END_FREE) {
        if (len > 0.0 || path) {
            snprintf(err, errlen, "implicit scheme: the %s is free, so it cannot %s; make it "
                     "pinned or clamped (ends.%s)", end_names[which],
                     path ? "follow a path (ends.*_motion)" : "slide (ends.*_slide)", end_names[which]);
            return -1;
        }
        return 0;
    }
    if (!isfinite(len)) {
        snprintf(err, errlen, "implicit scheme: the %s's slide (ends.%s_slide) must be a finite "
                 "direction", end_names[which], end_names[which]);
        return -1;
    }
    e->held = 1;
    e->path = path;
    if (len > 0.0) {
        e->sliding = 1;
        v3_scale(e->slide, slide, 1.0 / len);
        v3_copy(e->slide0, e->slide);
    }
    if (kind == ROD_END_CLAMPED) {
        if (e->sliding && path && twist_held) {
            /* a sleeve that moves and turns the end: the frame is the path's
             * (R(t) Q(0), d3 along the turned slide), the position free along it */
            e->clamped = 1;
        } else if (e->sliding) { /* d3 along the slide; it may twist, unless held (ends.*_twist) */
            e->hold_omega[0] = e->hold_omega[1] = 1;
            e->hold_omega[2] = twist_held;
        }
        else e->clamped = 1;
    } else if (which == 0) {
        e->hold_omega[2] = 1; /* a pinned root is a torsion stop (rod.h) */
    }
    return 0;
}

/* Both ends' conditions, and something that holds the rod's twist: -1 with
 * a message when the scheme cannot model them. */
static int read_ends(const rod_model *m, end_condition ends[2], char *err, size_t errlen)
{
    if (read_end(&ends[0], 0, m->root_end, m->root_slide, m->slide_twist_held[0], m->root_motion,
                 err, errlen) ||
        read_end(&ends[1], 1, m->tip_end, m->tip_slide, m->slide_twist_held[1], m->tip_motion,
                 err, errlen))
        return -1;
    int twist_held = ends[0].clamped || ends[0].hold_omega[2] || ends[1].clamped ||
                     ends[1].hold_omega[2];
    if (!twist_held && !(m->rotary_inertia[2] > 0.0)) {
        /* nothing resists a rigid turn of the rod about its own axis */
        static const char *const kinds[] = {"clamped", "pinned", "free"};
        snprintf(err, errlen, "implicit scheme: with ends root = %s%s, tip = %s%s nothing holds the "
                 "rod's twist, so it needs torsional inertia (physics.twist = 1 and "
                 "physics.rotary_inertia = 1), or an end clamped in place or a pinned root",
                 kinds[m->root_end], ends[0].sliding ? " (sliding)" : "", kinds[m->tip_end],
                 ends[1].sliding ? " (sliding)" : "");
        return -1;
    }
    return 0;
}

static int vector_zero(const double a[3]) { return a[0] == 0.0 && a[1] == 0.0 && a[2] == 0.0; }

/* The layout of the unknowns: the planar path or 3-D, the first node with
 * an omega block, the block's size and the band's half width. */
static void choose_layout(implicit_work *w, const rod_model *m)
{
    const end_condition *ends = w->ends;
    /* the planar path models today's cantilever only: the new ends, curvature,
     * point loads, moments and starting states are 3-D here */
    int plain = ends[0].clamped && !ends[0].path && m->tip_end == ROD_END_FREE &&
                vector_zero(m->intrinsic_curvature) && m->point_load_count == 0 &&
                vector_zero(m->distributed_moment) && !m->initial_shape &&
                m->initial_velocity[2] == 0.0 && m->direction[2] == 0.0 &&
                m->surface_count == 0 && m->puncture_count == 0 && m->instrument_count == 0 &&
                !m->segment_length; /* planar.c is written for a uniform grid */
    w->planar = m->physics.planar && rod_model_loads_planar(m) && plain;
    w->distributed_moment = !vector_zero(m->distributed_moment);
    w->first = (w->planar || ends[0].clamped) ? 1 : 0;
    w->blocks = m->nodes - w->first;
    w->block = w->planar ? BLOCK_PLANAR : BLOCK;
    /* punctures can be made by the needle during the run: a driven tip with
     * a needle and a tissue surface make room for them from the start */
    int tissue = 0;
    for (int k = 0; k < m->surface_count; k++) tissue |= m->surfaces[k].tissue;
    w->reach = (m->puncture_count > 0 || (tissue && m->needle_radius > 0.0) ||
                m->instrument_count > 0 || m->between_rods) ? 2 : 1; /* a grasp couples as a
                                                 puncture, a pair with another rod its segment */
    w->has_contact = m->surface_count > 0 || w->reach == 2 || m->between_rods;
    static const int kinds3[BLOCK] = {0, 0, 0, 2, 2, 2};
    static const int kinds2[BLOCK_PLANAR] = {0, 0, 1, 1, 2};
    memcpy(w->var_kind, w->planar ? kinds2 : kinds3, (size_t)w->block * sizeof(int));
    w->unknowns = w->block * w->blocks;
    w->max_reach = w->reach;
}

/* Every array of the work, sized for the model. Returns 0, or -1 when out
 * of memory. */
static int allocate(implicit_work *w, const rod_model *m)
{
    const size_t n = (size_t)m->nodes, u = (size_t)w->unknowns;
    int kl = w->planar ? BAND_PLANAR : BAND;
    if (w->reach == 2) kl = BAND_PUNCTURE;
    const int self = m->self_contact && !w->planar;
    /* the band's storage with the rows kernel's scratch when self-contact
     * solves the pairs' columns (implicit_solve_many) */
    if (band_lu_create(&w->lu, w->unknowns, kl, self)) return -1;
    double **vectors[] = {&w->x, &w->dx, &w->residual, &w->eval_x, &w->x_last, &w->x_before,
                          &w->x_before2, &w->perturbed};
    for (size_t k = 0; k < sizeof vectors / sizeof vectors[0]; k++)
        if (!(*vectors[k] = calloc(u, sizeof(double)))) return -1;
    /* (size per node, array) */
    struct { size_t per_node; double **array; } per_node[] = {
        {9, &w->frame0}, {3, &w->omega0}, {3, &w->vel0}, {3, &w->vel1}, {3, &w->d3mid0},
        {3, &w->moment0}, {9, &w->frame1}, {9, &w->frame_th}, {3, &w->darboux1}, {9, &w->mid1},
        {3, &w->d3mid1}, {3, &w->moment1}, {9, &w->save_frame}, {3, &w->save_pos},
        {3, &w->save_vel}, {3, &w->save_omega}, {3, &w->save_force}, {1, &w->phi0},
        {1, &w->phi1}, {1, &w->phi_th}, {18, &w->jac_node}, {36, &w->jac_seg}, {3, &w->vbar},
        {3, &w->pos0}};
    for (size_t k = 0; k < sizeof per_node / sizeof per_node[0]; k++)
        if (!(*per_node[k].array = calloc(n * per_node[k].per_node, sizeof(double)))) return -1;
    w->tipf0 = calloc(3, sizeof(double));
    w->tipm0 = calloc(3, sizeof(double));
    if (!w->tipf0 || !w->tipm0) return -1;
    const int held[2] = {w->ends[0].held, w->ends[1].held};
    if (rod_contact_create(&w->contact, m, w->pos0, w->vel1, w->vbar, held, w->has_contact))
        return -1;
    if (w->has_contact) {
        w->band_smooth = calloc((size_t)w->lu.ldab * u, sizeof(double));
        w->trail_jac = calloc(n * 27, sizeof(double));
        w->trail_touched = calloc(n, 1);
        if (!w->band_smooth || !w->trail_jac || !w->trail_touched) return -1;
    }
    if (self) {
        /* a graded grid: sized by its shortest segment, non-neighbours by
         * arc length (rod_self_contact_set_grid) */
        double shortest = m->ds;
        for (int j = 0; m->segment_length && j + 1 < m->nodes; j++)
            shortest = fmin(shortest, m->segment_length[j]);
        w->self = rod_self_contact_create(m->nodes, w->unknowns, w->first, BLOCK, m->diameter,
                                          shortest, m->self_friction);
        w->node_push = calloc(n, sizeof(double));
        if (!w->self || !w->node_push) return -1;
        if (m->segment_length && rod_self_contact_set_grid(w->self, m->segment_length, m->ds))
            return -1;
    }
    return 0;
}

/* The point loads gathered per node, and the largest force (N) and moment
 * (N m) among them. Returns 0, -1 when out of memory, -2 (message set) for a
 * load at a node the rod does not have. */
static int gather_point_loads(implicit_work *w, const rod_model *m, double *force_peak,
                              double *moment_peak, char *err, size_t errlen)
{
    *force_peak = *moment_peak = 0.0;
    if (m->point_load_count == 0) return 0;
    const size_t n = (size_t)m->nodes;
    w->point_force = calloc(n * 3, sizeof(double));
    w->point_moment = calloc(n * 3, sizeof(double));
    if (!w->point_force || !w->point_moment) return -1;
    for (int k = 0; k < m->point_load_count; k++) {
        const rod_point_load *pl = &m->point_loads[k];
        if (pl->node < 0 || pl->node >= m->nodes) {
            snprintf(err, errlen, "implicit scheme: point load %d is at node %d; nodes are "
                     "0..%d", k + 1, pl->node, m->nodes - 1);
            return -2;
        }
        v3_axpy(&w->point_force[3 * pl->node], 1.0, pl->force);
        v3_axpy(&w->point_moment[3 * pl->node], 1.0, pl->moment);
        *force_peak = fmax(*force_peak, v3_norm(pl->force));
        *moment_peak = fmax(*moment_peak, v3_norm(pl->moment));
    }
    return 0;
}

/* Scales: the largest of the applied loads and the rod's own elastic force
 * EI/L^2, so that an unloaded rod still has a sensible scale. */
static void set_scales(implicit_work *w, const rod_model *m, double point_peak,
                       double point_moment_peak)
{
    double L = m->length, EI = m->stiffness[0];
    double fpeak = 0.0, mmax = 0.0;
    if (m->profile.kind == ROD_PROFILE_TABLE && m->profile.table.columns == 7) {
        const rod_table *t = &m->profile.table;
        for (int r = 0; r < t->rows; r++)
            for (int k = 0; k < 3; k++) {
                fpeak = fmax(fpeak, fabs(t->data[r * 7 + 1 + k]));
                mmax = fmax(mmax, fabs(t->data[r * 7 + 4 + k]));
            }
    } else {
        double scale = 1.0;
        if (m->profile.kind == ROD_PROFILE_TABLE)
            for (int r = 0; r < m->profile.table.rows; r++)
                scale = fmax(scale, fabs(m->profile.table.data[2 * r + 1]));
        fpeak = scale * v3_norm(m->tip_force);
        mmax = scale * v3_norm(m->tip_moment);
    }
    double q = v3_norm(m->distributed_force) * L; /* N/m over the length */
    fpeak = fmax(fpeak, point_peak);
    mmax = fmax(fmax(mmax, point_moment_peak), v3_norm(m->distributed_moment) * L);
    w->force_scale = fmax(fmax(EI / (L * L), fpeak), fmax(mmax / L, q));
    w->moment_scale = w->force_scale * L;
    double f1 = rod_first_bending_frequency(m);
    w->var_scale[0] = w->force_scale;
    w->var_scale[1] = 2.0 * M_PI * f1 * L * 1e-3;
    w->var_scale[2] = 2.0 * M_PI * f1 * 1e-3;
}

implicit_work *implicit_create(const rod_model *m, char *err, size_t errlen)
{
    end_condition ends[2];
    if (read_ends(m, ends, err, errlen)) return NULL;
    implicit_work *w = calloc(1, sizeof *w);
    if (!w) goto oom;
    memcpy(w->ends, ends, sizeof ends);
    w->nodes = m->nodes;
    choose_layout(w, m);
    if (allocate(w, m)) goto oom;
    /* the finite differences never see contact (its part of the Jacobian is
     * in closed form: add_contact_jacobian), so friction's steep turn within
     * its creep speed does not ask for a smaller step */
    w->fd_step = 1e-7;
    double point_peak, point_moment_peak;
    int loads = gather_point_loads(w, m, &point_peak, &point_moment_peak, err, errlen);
    if (loads == -1) goto oom;
    if (loads == -2) {
        implicit_destroy(w);
        return NULL;
    }
    set_scales(w, m, point_peak, point_moment_peak);
    return w;
oom:
    snprintf(err, errlen, "implicit scheme: out of memory for %d nodes", m->nodes);
    implicit_destroy(w);
    return NULL;
}
