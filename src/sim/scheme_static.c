/* scheme_static.c: the static scheme (rod_scheme_static): the equilibrium
 * of the rod under the loads at s->time + dt, solved directly (no time
 * stepping): thesis (3.6) with the time derivatives dropped and (3.4) M =
 * B u, on the staggered grid of rod_geometry.h. A sequence of steps follows
 * the quasi-static load path: each step starts from the current state.
 *
 * This file is the scheme's entry (create, step, destroy); its stages are
 * the room src/sim/static/, with headers in include/sim/static/:
 *   static_work.c          the scratch memory: what the scheme refuses, the
 *                          ends' initial poses, the free rotations
 *   static_load.c          the loads and held ends' poses at a time, and the
 *                          load in words for messages
 *   static_solve.c         the discrete equations and end conditions, their
 *                          finite-difference Jacobian, the bordered band
 *                          solve of a Newton step
 *   static_stability.c     the tangent stiffness on the free rotations, its
 *                          negative eigenvalues, the critical mode
 *   static_settle.c        Newton and the descent to a rest, which watch the
 *                          stiffness; an unstable answer left along its
 *                          critical mode for a stable rest
 *   static_continuation.c  one step: the load path from the last answer to
 *                          the target in sub-steps, the starting shapes, the
 *                          answer written into the state
 *   static_mirror.c        the ends solved as the mirrored rod
 *   static_buckling.c      the straight rod's complex determinant, from which
 *                          rod_buckling_factor (buckling.h) finds where it
 *                          stops being stable
 *
 * The files call one another one way only, up this ladder (each includes
 * only the headers of files below it, and static_internal.h):
 *   work < load < solve < stability < settle < continuation < mirror < this file
 * static_buckling.c stands on solve alone; nothing in the room calls it.
 *
 * Every loop has a budget (Newton iterations, line-search halvings, load
 * sub-steps, descent iterations, solves per run), a load whose size in the
 * rod's scales is not finite is refused, and a bend of more than
 * ROD_UNRESOLVED_BEND between nodes is refused as the implicit scheme does. */
#include "sim/scheme_static.h"

#include <math.h>
#include <stdio.h>

#include "sim/rod.h"
#include "sim/static/static_continuation.h"
#include "sim/static/static_internal.h"
#include "sim/static/static_mirror.h"
#include "base/vec3.h"

/* The mirrored rod for a free root with a held tip, and for a sliding
 * root with a tip held in place (static_mirror_create); the rod itself
 * otherwise. */
static void *create(const rod_model *m, char *err, size_t errlen)
{
    if (rod_model_refuse_obstacles(m, "static", err, errlen)) return NULL;
    if (m->slide_twist_held[0] || m->slide_twist_held[1]) {
        snprintf(err, errlen, "static: ends.%s_twist = held (a carriage that does not turn) is "
                 "modelled by the implicit scheme only; use solver.scheme = implicit, or a "
                 "sleeve (free)", m->slide_twist_held[0] ? "root" : "tip");
        return NULL;
    }
    for (int e = 0; e < 2; e++)
        if ((e ? m->tip_motion : m->root_motion) && v3_norm(e ? m->tip_slide : m->root_slide) > 0.0) {
            snprintf(err, errlen, "static: the %s slides (ends.%s_slide) along a sleeve driven by "
                     "ends.%s_motion: a moving sleeve is modelled by the implicit scheme only; use "
                     "solver.scheme = implicit", e ? "tip" : "root", e ? "tip" : "root",
                     e ? "tip" : "root");
            return NULL;
        }
    int tip_in_place = m->tip_end != ROD_END_FREE && v3_norm(m->tip_slide) == 0.0;
    int mirrored = (m->root_end == ROD_END_FREE && m->tip_end != ROD_END_FREE) ||
                   (m->root_end != ROD_END_FREE && v3_norm(m->root_slide) > 0.0 && tip_in_place);
    if (mirrored && m->nodes >= 3 && m->ds > 0.0) return static_mirror_create(m, err, errlen);
    return static_work_create(m, err, errlen);
}

/* A mirrored rod's work owns its mirror, which frees both. */
static void destroy(void *work)
{
    static_work *w = work;
    if (w && w->mirror) static_mirror_destroy(w);
    else static_work_destroy(w);
}

static rod_status step(void *work, const rod_model *m, rod_state *s, double dt,
                       rod_report *report)
{
    static_work *w = work;
    if (w->mirror) return static_mirror_step(w, m, s, dt, report);
    return static_step_unmirrored(w, m, s, dt, report);
}

static double stable_dt(const rod_model *m, const char **limit)
{
    (void)m;
    if (limit) *limit = "static: no time step";
    return INFINITY;
}

const rod_scheme_ops rod_scheme_static = {"static", create, step, destroy, stable_dt, NULL};
