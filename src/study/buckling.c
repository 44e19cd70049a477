/* buckling.c: the load factor at which the straight rod stops being stable.
 *
 * The straight rod under axial tip loads (a force along x, a twisting moment
 * about x) is an equilibrium for every load factor lambda. It is stable while
 * the tangent stiffness of the discrete equilibrium (the static scheme's
 * Jacobian, scheme_static.h) at that straight state is regular and of the
 * unloaded rod's sign; the first lambda where it is singular is the critical
 * load (the onset of an adjacent bent equilibrium: buckling, divergence).
 *
 * The rod is round and the load axial, so bending modes come in pairs turned
 * 90 degrees about x and the real determinant has a double zero (no sign
 * change). The static scheme reports instead the complex determinant of the
 * transverse block (w = y + i z), which has a simple zero: its argument
 * jumps by pi there and stays constant between zeros (measured: 0, pi/2 or pi
 * to round-off for the cases in tests/study/test_buckling.c). A zero lies between
 * two load factors whose determinants differ in argument by more than pi/2.
 *
 * Search: lambda = 0, then from lambda_start (a load of 1/50 of the rod's
 * own scale EI/L^2, EI/L) up by factors of 1.15 to lambda_max, which
 * brackets the first zero; bisection then narrows it to the tolerance.
 *
 * A follower compressive force on a cantilever (Beck's column) never makes
 * the tangent singular: it loses stability by flutter, a dynamic instability
 * that a static criterion cannot see; the search reports no loss of
 * stability up to lambda_max. */
#include "study/buckling.h"

#include <math.h>
#include <stdio.h>

#include "sim/scheme_static.h"
#include "base/numfmt.h"
#include "base/vec3.h"

static const double scan_growth = 1.15;
static const double scan_start_size = 0.02; /* first nonzero load, in EI/L^2 and EI/L units */
static const int max_bisections = 100;      /* 2^-100: below any tolerance in doubles */

typedef struct probe {
    double lambda, log_abs, phase;
} probe;

static int probe_at(static_work *w, const rod_model *m, double lambda, probe *p, char *err,
                    size_t errlen)
{
    double residual;
    p->lambda = lambda;
    if (static_straight_determinant(w, m, lambda, &p->log_abs, &p->phase, &residual, err, errlen))
        return -1;
    if (!(residual < 1e-6)) {
        char said[NUMFMT_WORDS_MAX];
        snprintf(err, errlen,
                 "buckling: the straight rod is not an equilibrium at lambda = %g (scaled "
                 "residual %s)", lambda, numfmt_e_or_words(said, sizeof said, residual, 2));
        return -1;
    }
    return 0;
}

/* 1 when a zero of the determinant lies between a and b (or on b). */
static int crossed(const probe *a, const probe *b)
{
    return isinf(b->log_abs) || cos(b->phase - a->phase) < 0.0;
}

/* axial: along d3 for a follower load, along global x for a dead one */
static int load_axis(const rod_model *m)
{
    return m->tip_frame == ROD_FRAME_DIRECTOR ? 2 : 0;
}

static const char *load_axis_name(const rod_model *m)
{
    return m->tip_frame == ROD_FRAME_DIRECTOR ? "d3" : "x";
}

static int check_arguments(double lambda_max, double relative_tolerance, char *err,
                           size_t errlen)
{
    if (!(lambda_max > 0.0) || !isfinite(lambda_max)) {
        snprintf(err, errlen, "buckling: lambda_max must be > 0 (got %g)", lambda_max);
        return -1;
    }
    if (!(relative_tolerance > 0.0 && relative_tolerance <= 0.1)) {
        snprintf(err, errlen, "buckling: relative_tolerance must be in (0, 0.1] (got %g)",
                 relative_tolerance);
        return -1;
    }
    return 0;
}

/* Every load axial, so that the straight rod is an equilibrium at every lambda. */
static int check_loads_axial(const rod_model *m, char *err, size_t errlen)
{
    int axis = load_axis(m);
    for (int k = 0; k < 3; k++) {
        if (k == axis) continue;
        if (m->tip_force[k] != 0.0 || m->tip_moment[k] != 0.0) {
            snprintf(err, errlen,
                     "buckling: the tip force (%g %g %g N) and moment (%g %g %g N m) must lie "
                     "along %s so that the straight rod is an equilibrium; a transverse load "
                     "bends it from the start (solve it with the static scheme instead)",
                     m->tip_force[0], m->tip_force[1], m->tip_force[2], m->tip_moment[0],
                     m->tip_moment[1], m->tip_moment[2], load_axis_name(m));
            return -1;
        }
    }
    if (v3_norm(m->distributed_force) != 0.0) {
        snprintf(err, errlen,
                 "buckling: the distributed force (gravity) must be zero (got %g %g %g N/m): "
                 "it bends the straight rod", m->distributed_force[0], m->distributed_force[1],
                 m->distributed_force[2]);
        return -1;
    }
    /* The straight state is the rod along +x from its root, every load
     * axial: anything else bends it from the start (or, a tip held in place,
     * carries the axial load itself: the straight rod is then unloaded). */
    if (v3_norm(m->intrinsic_curvature) != 0.0 || v3_norm(m->distributed_moment) != 0.0 ||
        m->point_load_count > 0 || m->initial_shape) {
        snprintf(err, errlen,
                 "buckling: the straight rod must be an equilibrium: no intrinsic curvature (rod.curvature), "
                 "point loads, distributed moment or initial shape (got |u0| = %g 1/m, %d point "
                 "loads, |m| = %g N m/m%s); solve such a rod with the static scheme instead",
                 v3_norm(m->intrinsic_curvature), m->point_load_count,
                 v3_norm(m->distributed_moment), m->initial_shape ? ", an initial shape" : "");
        return -1;
    }
    return 0;
}

/* The rod along +x, its ends held still, a held tip on an axial slide, no mechanism. */
static int check_ends(const rod_model *m, char *err, size_t errlen)
{
    if (!(m->direction[0] > 0.0 && m->direction[1] == 0.0 && m->direction[2] == 0.0)) {
        snprintf(err, errlen, "buckling: the rod must start along +x (rod.direction = 1 0 0; got "
                 "%g %g %g): the tip loads' axial component is taken along x",
                 m->direction[0], m->direction[1], m->direction[2]);
        return -1;
    }
    if (m->tip_end != ROD_END_FREE &&
        !(m->tip_slide[0] > 0.0 && m->tip_slide[1] == 0.0 && m->tip_slide[2] == 0.0)) {
        snprintf(err, errlen,
                 "buckling: a held tip must slide along the rod's axis (ends.tip_slide = 1 0 0, "
                 "Euler's sleeve; got %g %g %g) so that the axial load reaches the rod; a tip "
                 "held in place carries it itself. Drive the tip towards the root with the "
                 "static scheme instead (ends.tip_motion)",
                 m->tip_slide[0], m->tip_slide[1], m->tip_slide[2]);
        return -1;
    }
    if (m->root_motion || m->tip_motion) {
        snprintf(err, errlen, "buckling: the ends must be held still (no root_motion or tip_motion)");
        return -1;
    }
    /* The static scheme solves a rod hanging from a pin, but its
     * straight state under an axial tip force has no critical load to scale
     * to: the rod swings about the pin (an inverted pendulum when pushed). */
    if (m->root_end == ROD_END_PINNED && m->tip_end == ROD_END_FREE) {
        snprintf(err, errlen,
                 "buckling: ends root = pinned, tip = free make a mechanism for an axial load: "
                 "pushed, the straight rod falls over about the pin at any load (critical "
                 "factor 0); pulled, it never buckles. Clamp the root, or hold the tip "
                 "(tip = pinned or clamped, tip_slide = 1 0 0)");
        return -1;
    }
    return 0;
}

/* The load in the rod's own scale, |F| L^2/EI + |M| L/EI; -1 when not finite and > 0. */
static double load_size(const rod_model *m, char *err, size_t errlen)
{
    int axis = load_axis(m);
    const char *axis_name = load_axis_name(m);
    double ei = m->stiffness[0], length = m->length;
    double size = fabs(m->tip_force[axis]) * length * length / ei +
                  fabs(m->tip_moment[axis]) * length / ei;
    if (!isfinite(size)) { /* scan_start_size / size would be 0: a scan that never moves */
        snprintf(err, errlen, "buckling: the tip force (%g N) and moment (%g N m) along %s overflow "
                 "the rod's own scale (|F| L^2/EI + |M| L/EI is not finite, EI = %g N m^2): give "
                 "a load of the order of EI/L^2 = %g N", m->tip_force[axis], m->tip_moment[axis],
                 axis_name, ei, ei / (length * length));
        return -1.0;
    }
    if (!(size > 0.0)) {
        snprintf(err, errlen, "buckling: the tip force and moment along %s are both zero: "
                 "nothing to scale", axis_name);
        return -1.0;
    }
    return size;
}

/* From lambda = 0 up by scan_growth to lambda_max: low and high bracket the first zero.
 * Returns 0 when bracketed, -1 (err written) otherwise. */
static int scan_for_zero(static_work *w, const rod_model *m, double lambda_max, double size,
                         probe *low, probe *high, char *err, size_t errlen)
{
    if (probe_at(w, m, 0.0, low, err, errlen)) return -1;
    double next = fmin(lambda_max, scan_start_size / size);
    for (;;) {
        if (probe_at(w, m, next, high, err, errlen)) return -1;
        if (crossed(low, high)) return 0;
        if (next >= lambda_max) break;
        *low = *high;
        next = fmin(lambda_max, next * scan_growth);
    }
    int axis = load_axis(m);
    snprintf(err, errlen,
             "buckling: no loss of stability of the straight rod up to lambda = %g (tip "
             "force %g N, moment %g N m along %s, on the %s frame): the tangent stiffness "
             "stays regular%s", lambda_max, lambda_max * m->tip_force[axis],
             lambda_max * m->tip_moment[axis], load_axis_name(m),
             m->tip_frame == ROD_FRAME_DIRECTOR ? "follower (tip director)" : "dead (global)",
             m->tip_frame == ROD_FRAME_DIRECTOR
                 ? ". A follower compressive force on a cantilever (Beck's column) is like "
                   "that: it loses stability by flutter, which a static criterion cannot detect"
                 : "");
    return -1;
}

/* Bisection of the bracket to the tolerance; the critical factor in *lambda. */
static int bisect(static_work *w, const rod_model *m, double relative_tolerance, probe low,
                  probe high, double *lambda, char *err, size_t errlen)
{
    /* a budget: halving cannot narrow the bracket below the spacing of
     * doubles, so a tolerance under ~1e-16 would loop for ever without one */
    for (int halving = 0; halving < max_bisections && high.lambda - low.lambda >
                                                          relative_tolerance * high.lambda &&
                          !isinf(high.log_abs);
         halving++) {
        probe middle;
        if (probe_at(w, m, 0.5 * (low.lambda + high.lambda), &middle, err, errlen)) return -1;
        if (crossed(&low, &middle)) high = middle;
        else low = middle;
    }
    *lambda = isinf(high.log_abs) ? high.lambda : 0.5 * (low.lambda + high.lambda);
    return 0;
}

int rod_buckling_factor(const rod_model *m, double lambda_max, double relative_tolerance,
                        double *lambda, char *err, size_t errlen)
{
    if (check_arguments(lambda_max, relative_tolerance, err, errlen) ||
        check_loads_axial(m, err, errlen) || check_ends(m, err, errlen))
        return -1;
    double size = load_size(m, err, errlen);
    if (size < 0.0) return -1;
    static_work *w = static_work_create(m, err, errlen);
    if (!w) return -1;
    probe low, high;
    int rc = scan_for_zero(w, m, lambda_max, size, &low, &high, err, errlen);
    if (rc == 0) rc = bisect(w, m, relative_tolerance, low, high, lambda, err, errlen);
    static_work_destroy(w);
    return rc;
}
