/* scheme_thesis.c: chapter 4 of the thesis as written: forward Euler in time,
 * central differences in space (4.3), one collocated grid (staggered = 0).
 *
 * One step j -> j+1 (t -> t + dt), in this order:
 *   1. u      (4.5)   from omega^j, at i = 0 .. NS-2; u(NS-1) = B^-1 M_bar (4.2)
 *   2. frames (4.6)-(4.8) marched from the clamp with u^{j+1}
 *   3. omega  (4.12)  from u^{j+1}, N^j, omega^j; omega(0) = 0 (4.2)
 *   4. v      (4.10)  marched from the clamp with omega^{j+1}, u^{j+1}; v(0) = 0
 *   5. N      (4.14)  marched from the free end, v-dot = (v^{j+1} - v^j)/dt; N(NS-1) = N_bar
 *   6. centreline (4.16) from d3^{j+1}
 *
 * Choices where the text is ambiguous (each has a test in tests/sim/test_scheme_thesis.c):
 *  - Order of v and omega: the text lists v (4.10) before omega (4.12), yet
 *    (4.10) uses omega(i, j+1). We compute omega first, so every superscript
 *    in (4.10), (4.12) and (4.14) holds as printed: (4.12) needs only u^{j+1}
 *    and N^j, not v.
 *  - v-dot in (4.13): (v^{j+1} - v^j)/dt, the forward difference of (4.3).
 *  - Starting a march: (4.10), (4.14) and (4.16) are leapfrogs in s
 *    (a(i+1) = a(i-1) + 2 ds a'(i)) and need two starting values. The second
 *    one comes from one trapezoidal step, a(1) = a(0) + ds/2 (a'(0) + a'(1))
 *    (implicit in a(1) only through u x a: a 3x3 solve in closed form), so
 *    both sub-lattices (odd, even nodes) start second-order accurate. An
 *    Euler start would make v(1) = 0 always (omega(0) = v(0) = 0).
 *  - Derivatives at the ends in the time updates: one-sided, first order:
 *    omega'(0) = (omega(1) - omega(0))/ds in (4.5), u'(NS-1) = (u(NS-1) -
 *    u(NS-2))/ds in (4.12). With these the static equilibrium of the scheme
 *    has u exactly linear under a tip force (no odd/even zig-zag).
 *  - Rotation angle in (4.6): the text uses sin(ds) and 1 - cos(ds) with the
 *    unnormalised u-tilde: not a rotation unless |u| = 1 1/m, and
 *    dimensionally an angle ds in metres. options.exact_rotation = 1
 *    (default) uses exp(ds [u]x) (angle |u| ds); 0 uses (4.6) literally.
 *    For small |u| ds both agree to second order in ds (sin ds ~ ds).
 *  - Sign of (4.7)/(4.8): (3.1)_1, d_k' = u x d_k with u = u_a d_a, gives
 *    Q' = Q [u]x for Q with columns d1 d2 d3 (director components). The
 *    u-tilde of (4.8) is exactly [u]x written in the order {d3, d1, d2};
 *    applied as (4.7) prints it (left-multiplying the list of directors) it
 *    would turn the frame by -u. We use Q_{i+1} = Q_i R_i (right-multiplying
 *    the frame matrix), which is what (3.1)_1 requires.
 *  - Frames use u(i) over the segment i -> i+1, as (4.7) writes R_i: first
 *    order in ds. Under a tip force P this overestimates the slope and the
 *    static tip deflection by about (3/4) ds/L (1.5 % at NS = 51).
 *  - Centreline (4.16) starts with R(1) = R(0) + ds/2 (d3(0) + d3(1)).
 *
 * Stability (von Neumann, linearised about the straight rod at rest; checked
 * by bisection in the tests). Planar bending, mode with spatial symbol kappa
 * (kappa^2 the eigenvalue of -d^2/ds^2 with omega = v = 0 at the clamp and
 * N = 0, u = 0 at the tip; kappa_min = pi/(2L)):
 *   (4.5)  u^{j+1} = u^j + dt i kappa omega^j
 *   (4.10) v^{j+1} = omega^{j+1} / (i kappa)
 *   (4.14) N^{j+1} = -(m/kappa^2) (omega^{j+1} - omega^j)/dt - (c/kappa^2) omega^{j+1}
 *   (4.12) I_s (omega^{j+1} - omega^j) = dt (B i kappa u^{j+1} + N^j)
 * With a = m/(I_s kappa^2), b = dt^2 B kappa^2 / I_s, e = dt c/(I_s kappa^2)
 * this is z^3 + (a+b+e-2) z^2 + (1-2a-e) z + a = 0 and the Jury conditions
 * give: stable iff a < 1 and b + 2e < 4 (1 - a).
 *   - a < 1 for the lowest mode: the lag of N (N^j in (4.12), N from v-dot)
 *     amplifies by -a per step whatever dt is. Physical inertia, table 1:
 *     a = 64 L^2/(pi^2 d^2) = 6.5e6, so rotary_inertia_scale must exceed
 *     64 L^2/(pi^2 d^2) (rho I s = m/kappa_min^2).
 *   - b < 4 (1 - a) at kappa_max = 1/ds (the rotation wave of speed
 *     sqrt(E/(rho s))): dt < 2 ds sqrt(rho s/E) sqrt(1 - 16 ds^2/(d^2 s)).
 *   - twist (u3, omega3; no N coupling): dt < 2 ds sqrt(rho s/G).
 * The stable_dt below evaluates these conditions (damping included) over the
 * discrete modes; the twist limit only where torsion is dynamic (see below).
 * Measured (spectral radius of the step's Jacobian, finite differences about
 * the straight rod, scale 1e7): the largest constant dt is 0.9666 s at NS = 21
 * (predicted 0.9836: the one-sided ends shift the top mode), 0.3941 s at
 * NS = 51 and 0.1971 s at NS = 101 (both within 0.1 %); 0.1 % above it the
 * top bending mode grows by 1.1 to 1.26 per step, so no slow mode hides
 * below the limit at a constant step.
 *
 * Steps of changing size: the limit above holds for a CONSTANT dt only. Each
 * step with dt_j is a map that conserves its own dt-dependent quadratic form
 * (for (4.5) with (4.12), symplectic Euler per mode: omega^2 + c^2 kappa^2 u^2
 * - dt c^2 kappa^2 u omega ...), and the lag of N (4.14) enters (4.12) as
 * a (dt_j/dt_{j-1}) (omega^j - omega^{j-1}). A periodic change of dt (a run
 * landing on output times: 4 x 0.197 s + 2 x 0.106 s per 1 s frame) switches
 * between these forms and pumps every mode whose frequency is a multiple of
 * half the switching frequency (parametric resonance, eigenvalue near -1 per
 * period): measured growth 1.094 per period (bending) and 1.059 (twist) at
 * NS = 51, dt 0.197 s, divergence after ~1400 steps; 1.001 to 1.015 per step
 * for any dt from 0.11 s to 0.2 s with that pattern, none at dt = 0.1 s
 * (10 equal steps). Long runs (5000 steps, 1 s frames) fail from dt = 0.163 s
 * at NS = 51 and from 0.070 s at NS = 101 (limit 0.197 s) with uneven steps,
 * and run at every dt below the limit with equal ones. The cure is equal steps
 * (a caller splitting an interval into n equal steps), not a smaller dt: the
 * step records the range of dt it was given and the divergence message says
 * when it varied.
 *
 * Under a load there is a slow growth at ANY constant dt: about the loaded
 * equilibrium the out-of-plane bending + twist mode (u1, u3, omega1, omega3)
 * has spectral radius 1 + 4.5e-6 (dt 0.1 s), 1 + 1.8e-5 (0.2 s) at 0.5 x the
 * Euler load and 1 + 9e-6 (0.05 s), 1 + 1.5e-4 (0.2 s), 1 + 5.9e-4 (0.4 s) at
 * 1 x (NS = 51, scale 1.3e7): O(dt^2) per step, O(dt) per second, so it is the
 * time discretisation, consistent with N^j of (4.12) carrying delta u^j x N
 * ((4.14), one step old) where symplectic Euler would need u^{j+1}. A planar
 * load never seeds it (u1 = u3 = 0 exactly); a random seed does: `rodsim
 * stability`'s trial under 1 x the Euler load (transverse, undamped swing)
 * stretches 1 % after 2000 to 5400 steps (~900 to 1200 s) at 0.5 to 0.99 x
 * the limit. linear_damping does not remove it: with c = 1e-3 N s/m^2 the
 * same mode grows at 1.8e-3 1/s whatever dt (0.05, 0.2 s) and NS (21, 51,
 * 101): u1 from 1e-6 to 7.5e-3 in 4000 s at dt 0.1 s, then saturates (a slow
 * out-of-plane whirl). Its source is not identified (open question).
 *
 * Segment length: (4.16) builds the centreline from d3 with a leapfrog in s,
 * so odd and even nodes lie on two separately marched polygons; the segment
 * between them is ds only while d3 is smooth on the scale of ds (relative
 * error ~ (|u| ds)^2, 2e-6 .. 5e-5 for table 2). An odd/even zig-zag of d3 (a
 * diverging mode that central differences (4.5), (4.12) do not see) or an
 * unresolved curvature separates the two polygons: the rod stretches with no
 * NaN and no large u anywhere. The positions are not integrated: they follow
 * d3 every step, so the stretch is the only trace. The step checks it: more
 * than twice what the curvature explains (at least STRETCH_LIMIT), or more
 * than STRETCH_LIMIT with |u| ds > MAX_TURN, is a diverged run.
 *
 * Physics switches (rod_physics):
 *  - twist = 0: quasi-static twist, no torsional inertia (rho J = 0). The d3
 *    component of (4.12) becomes the equilibrium of M3 along the rod,
 *    C u3' + (u x B u)_3 = 0 with (u x B u)_3 = (B2 - B1) u1 u2 = 0 for the
 *    round section: u3 = M3_bar / C at every node (4.2). omega3 then follows
 *    from the d3 component of compatibility (4.5), omega3' = u3_t - (u x omega)_3,
 *    marched from the clamp (omega3(0) = 0) with the trapezoidal rule. No
 *    twist wave, so no twist step limit. Angular damping then acts on the
 *    bending rotations only (a damped quasi-static twist would be a diffusion
 *    with its own explicit limit).
 *  - twist = 1 with loads in the x-y plane (rod_model_loads_planar): u1, omega1,
 *    u3, omega3 stay exactly 0 (no term of (4.5), (4.12) creates them), so the
 *    twist wave is never excited and does not cap dt. A non-planar load with no
 *    twisting moment still excites twist at second order through (u x omega)_3:
 *    the cap stays; twist = 0 removes it.
 *  - rotary_inertia = 0: impossible here, (4.12) divides by rho I: refused. */
#include "sim/rod.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"

/* Divergence detection: max|omega| growing by more than this factor in
 * GROWTH_STEPS consecutive steps is numerical (a physical growth e^{sigma dt}
 * that fast would not be resolved anyway); a load switched on once gives
 * one large ratio, never two in a row. */
#define GROWTH_FACTOR 10.0
#define GROWTH_STEPS 2
/* Largest relative segment-length error |r_{i+1} - r_i|/ds - 1 a run may reach
 * beyond what its curvature explains (see the step): table 2 stays below 1e-4
 * (5e-5 after 20000 steps at its own dt); 1000 x the Euler load reached 93 %. */
#define STRETCH_LIMIT 0.01
#define MAX_TURN 1.0 /* rad, |u| ds: 57 degrees per segment */

typedef struct thesis_work {
    int nodes;
    double *old_velocity; /* (nodes x 3), m/s, v^j for v-dot in (4.13) */
    double *new_omega;    /* (nodes x 3), rad/s, omega^{j+1} while (4.12) reads omega^j */
    double previous_max_omega; /* rad/s, max |omega| after the last step */
    int growth_count;          /* consecutive steps with growth > GROWTH_FACTOR */
    double last_growth;        /* max|omega| ratio of the last finite step */
    long steps;                /* steps taken since create */
    double smallest_dt, largest_dt; /* s, over the steps of this run */
} thesis_work;

/* Stability limits ---------------------------------------------------- */

/* Smallest rotary_inertia_scale with a < 1 for the lowest mode. */
static double minimum_scale(const rod_model *m)
{
    double theta = M_PI * m->ds / (2.0 * m->length);
    double kappa_min = sin(theta) / m->ds; /* central-difference symbol */
    double physical = m->density * m->second_moment;
    return m->mass_per_length / (physical * kappa_min * kappa_min);
}

/* Largest dt with b + 2e < 4 (1 - a) for a mode kappa, or 0 when a >= 1. */
static double bending_mode_dt(double kappa, double inertia, double stiffness, double mass,
                              double damping)
{
    double k2 = kappa * kappa;
    double a = mass / (inertia * k2);
    if (a >= 1.0) return 0.0;
    /* (B k2/I) dt^2 + (2 c/(I k2)) dt - 4 (1 - a) = 0, positive root */
    double qa = stiffness * k2 / inertia, qb = 2.0 * damping / (inertia * k2), qc = -4.0 * (1.0 - a);
    return (-qb + sqrt(qb * qb - 4.0 * qa * qc)) / (2.0 * qa);
}

static const char *const LIMIT_INERTIA =
    "rotary inertia: m/(rho I s kappa_min^2) < 1, i.e. rotary_inertia_scale > 64 L^2/(pi^2 d^2); "
    "unstable for every dt below it";
static const char *const LIMIT_BENDING_LOW =
    "bending, lowest mode: dt^2 EI kappa^2/(rho I s) < 4 (1 - m/(rho I s kappa^2)), kappa = pi/(2L)";
static const char *const LIMIT_BENDING_HIGH =
    "bending rotation wave: dt < 2 ds sqrt(rho s/E) sqrt(1 - 16 ds^2/(d^2 s))";
static const char *const LIMIT_TWIST = "twist: dt < 2 ds / sqrt(G/(rho s))";
static const char *const LIMIT_ANGULAR_DAMPING = "angular damping: dt < 2 rho I s / c_w";

/* 1 when the twist wave is part of the dynamics: torsional inertia on and a
 * load that can excite u3 (not planar). */
static int twist_dynamic(const rod_model *m)
{
    return m->physics.twist && !rod_model_loads_planar(m);
}

/* The predicted largest stable dt at rotary_inertia_scale `scale`, s. */
static double thesis_limit(const rod_model *m, double scale, const char **limit)
{
    const char *which = LIMIT_INERTIA;
    if (scale * (1.0 - 1e-12) <= minimum_scale(m)) {
        if (limit) *limit = which;
        return 0.0;
    }
    double inertia = m->density * m->second_moment * scale; /* bending, kg m */
    double best = INFINITY;
    /* discrete modes theta = (2n-1) pi ds/(2L) up to pi/2 (kappa = 1/ds);
       beyond pi/2 the central-difference symbol sin(theta)/ds repeats */
    for (int n = 1;; n++) {
        double theta = (2 * n - 1) * M_PI * m->ds / (2.0 * m->length);
        int last = theta >= M_PI / 2.0;
        if (last) theta = M_PI / 2.0;
        double kappa = sin(theta) / m->ds;
        double dt = bending_mode_dt(kappa, inertia, m->stiffness[0], m->mass_per_length,
                                    m->linear_damping);
        if (dt < best) {
            best = dt;
            which = n == 1 ? LIMIT_BENDING_LOW : LIMIT_BENDING_HIGH;
        }
        if (last) break;
    }
    double twist = twist_dynamic(m) ? 2.0 * m->ds / sqrt(m->shear_modulus / (m->density * scale))
                                    : INFINITY;
    if (twist < best) {
        best = twist;
        which = LIMIT_TWIST;
    }
    if (m->angular_damping > 0.0) {
        double damping = 2.0 * inertia / m->angular_damping;
        if (damping < best) {
            best = damping;
            which = LIMIT_ANGULAR_DAMPING;
        }
    }
    if (limit) *limit = which;
    return best;
}

static double stable_dt(const rod_model *m, const char **limit)
{
    return thesis_limit(m, m->rotary_inertia_scale, limit);
}

/* Create / destroy ------------------------------------------------------ */

static void destroy(void *work)
{
    thesis_work *w = work;
    if (!w) return;
    free(w->old_velocity);
    free(w->new_omega);
    free(w);
}

static void *create(const rod_model *m, char *err, size_t errlen)
{
    /* chapter 5: "the scheme ... can be used only where the boundary conditions are of the
     * mixed kind"; and (4.12) divides by the rotary inertia */
    if (rod_model_require_cantilever(m, "thesis", err, errlen) ||
        rod_model_refuse_obstacles(m, "thesis", err, errlen))
        return NULL;
    if (!m->physics.rotary_inertia || !(m->rotary_inertia[0] > 0.0) ||
        (m->physics.twist && !(m->rotary_inertia[2] > 0.0))) {
        snprintf(err, errlen, "the thesis scheme needs the rotary inertia: (4.12) divides by rho I "
                              "(an explicit update of omega has nothing to update without it); "
                              "set [physics] rotary_inertia = on (twist = off is accepted: "
                              "quasi-static twist), or use scheme = implicit");
        return NULL;
    }
    thesis_work *w = calloc(1, sizeof *w);
    if (!w) {
        snprintf(err, errlen, "thesis scheme: out of memory");
        return NULL;
    }
    w->nodes = m->nodes;
    w->old_velocity = calloc((size_t)m->nodes * 3, sizeof(double));
    w->new_omega = calloc((size_t)m->nodes * 3, sizeof(double));
    if (!w->old_velocity || !w->new_omega) {
        destroy(w);
        snprintf(err, errlen, "thesis scheme: out of memory for %d nodes", m->nodes);
        return NULL;
    }
    return w;
}

/* Small helpers ---------------------------------------------------------- */

/* x solving x + a x x_ = b, i.e. (I + [a]x) x = b:
 * x = (b - a x b + (a.b) a) / (1 + |a|^2). */
static void solve_plus_cross(double x[3], const double a[3], const double b[3])
{
    double axb[3];
    v3_cross(axb, a, b);
    double k = 1.0 / (1.0 + v3_dot(a, a));
    double ab = v3_dot(a, b);
    for (int c = 0; c < 3; c++) x[c] = k * (b[c] - axb[c] + ab * a[c]);
}

/* Rotation over one segment: exp(ds [u]x), or (4.6) literally. */
static void segment_rotation(double r[9], const double u[3], double ds, int exact)
{
    if (exact) {
        double phi[3];
        v3_scale(phi, u, ds);
        m3_exp(r, phi);
        return;
    }
    /* (4.6): R = I + sin(ds) [u]x + (1 - cos ds) [u]x^2 (see the sign note above) */
    double k[9] = {0, -u[2], u[1],
                   u[2], 0, -u[0],
                   -u[1], u[0], 0};
    double k2[9];
    m3_mul(k2, k, k);
    double a = sin(ds), b = 1.0 - cos(ds);
    for (int c = 0; c < 9; c++) r[c] = ((c % 4 == 0) ? 1.0 : 0.0) + a * k[c] + b * k2[c];
}

static double max_norm(const double *a, int nodes)
{
    double worst = 0.0;
    for (int i = 0; i < nodes; i++) {
        double n = v3_norm(&a[3 * i]);
        if (!(n <= worst)) worst = n; /* NaN propagates */
    }
    return worst;
}

/* 1 when twist carries most of the rotational kinetic energy (J omega3^2
 * against I (omega1^2 + omega2^2)): the diverging mode is a twist mode. */
static int twist_dominates(const rod_model *m, const rod_state *s)
{
    double twist = 0.0, bending = 0.0;
    for (int i = 0; i < s->nodes; i++) {
        const double *w = &s->angular_velocity[3 * i];
        twist += m->rotary_inertia[2] * w[2] * w[2];
        bending += m->rotary_inertia[0] * (w[0] * w[0] + w[1] * w[1]);
    }
    return twist > bending; /* NaN: 0, bending */
}

/* `advice`: what would work, or NULL for the rotary inertia and dt of the limit. */
static rod_status unstable(const rod_model *m, const thesis_work *w, const rod_state *state,
                           rod_report *r, const char *what, const char *advice)
{
    const double time = state->time;
    const char *limit = NULL;
    double limit_dt = thesis_limit(m, m->rotary_inertia_scale, &limit);
    if (limit_dt > 0.0 && twist_dynamic(m) && twist_dominates(m, state)) {
        /* the growing mode is twist: name its limit, not the (smaller) bending one */
        limit = LIMIT_TWIST;
        limit_dt = 2.0 * m->ds / sqrt(m->shear_modulus / (m->density * m->rotary_inertia_scale));
    }
    char varied[256] = "";
    if (w->largest_dt > w->smallest_dt * (1.0 + 1e-6))
        snprintf(varied, sizeof varied,
                 " The steps changed size (%.4g s to %.4g s): the limit holds for a constant dt; "
                 "steps of changing size pump modes parametrically below it, so take equal "
                 "steps (e.g. a dt that divides the output interval 1/fps).",
                 w->smallest_dt, w->largest_dt);
    double scale = m->rotary_inertia_scale;
    double min_scale = minimum_scale(m);
    if (limit_dt <= 0.0) {
        /* 1.5 x the threshold, rounded up to 2 significant digits */
        double want = 1.5 * min_scale;
        double unit = pow(10.0, floor(log10(want)) - 1.0);
        scale = ceil(want / unit) * unit;
    }
    double dt_ok = 0.5 * thesis_limit(m, scale, NULL);
    r->suggested_scale = scale;
    r->suggested_dt = dt_ok;
    if (advice) {
        snprintf(r->message, sizeof r->message,
                 "thesis scheme diverged at step %ld (t = %.6g s): %s. Predicted largest stable "
                 "dt %.3g s (%s).%s What would work: %s",
                 w->steps, time, what, limit_dt, limit, varied, advice);
        return ROD_UNSTABLE;
    }
    snprintf(r->message, sizeof r->message,
             "thesis scheme diverged at step %ld (t = %.6g s): %s. Limit broken: %s "
             "(rotary_inertia_scale = %.3g, threshold %.3g; predicted largest stable dt %.3g s).%s "
             "What would work: rotary_inertia_scale = %.3g with dt <= %.3g s "
             "(a scaled inertia slows the bending dynamics), or scheme = implicit.",
             w->steps, time, what, limit, m->rotary_inertia_scale, min_scale, limit_dt, varied,
             scale, dt_ok);
    return ROD_UNSTABLE;
}

/* Largest relative segment-length error |r_{i+1} - r_i|/ds - 1 (NaN propagates),
 * and the segment where it is. */
static double worst_stretch(const rod_model *m, const rod_state *s, int *segment)
{
    double worst = 0.0;
    *segment = 0;
    for (int i = 0; i + 1 < s->nodes; i++) {
        double d[3];
        v3_sub(d, &s->position[3 * (i + 1)], &s->position[3 * i]);
        double e = fabs(v3_norm(d) - m->ds) / m->ds;
        if (!(e <= worst)) {
            worst = e;
            *segment = i;
        }
    }
    return worst;
}

/* The step ------------------------------------------------------------------ */

static const double E3[3] = {0.0, 0.0, 1.0}; /* d3 in director components */

/* A finite dt > 0 and the model's node count; a fresh (or reset) run forgets the last
 * run's history. */
static rod_status begin_step(thesis_work *w, rod_state *s, double dt, rod_report *report)
{
    s->staggered = 0;
    if (!(dt > 0.0) || !isfinite(dt) || s->nodes != w->nodes) {
        snprintf(report->message, sizeof report->message,
                 "thesis scheme: dt must be a finite number > 0 s (got %g) and the state must have "
                 "the model's %d nodes", dt, w->nodes);
        return ROD_FAILED;
    }
    if (s->time == 0.0) { /* a fresh (or reset) run: forget the last run's history */
        w->steps = 0;
        w->previous_max_omega = 0.0;
        w->growth_count = 0;
        w->last_growth = 0.0;
        w->smallest_dt = w->largest_dt = dt;
    }
    w->steps++;
    if (dt < w->smallest_dt) w->smallest_dt = dt;
    if (dt > w->largest_dt) w->largest_dt = dt;
    return ROD_OK;
}

/* 1. (4.5) u(j+1) = u(j) + dt (omega' + u x omega) */
static void update_curvature(const rod_model *m, rod_state *s, double dt, int components)
{
    const int tip = m->nodes - 1;
    const double ds = m->ds;
    double *u = s->darboux, *om = s->angular_velocity;
    for (int i = 0; i < tip; i++) {
        double dw[3], uxw[3];
        if (i == 0) { /* one-sided at the clamp */
            v3_sub(dw, &om[3], &om[0]);
            v3_scale(dw, dw, 1.0 / ds);
        } else {
            v3_sub(dw, &om[3 * (i + 1)], &om[3 * (i - 1)]);
            v3_scale(dw, dw, 0.5 / ds);
        }
        v3_cross(uxw, &u[3 * i], &om[3 * i]);
        for (int c = 0; c < components; c++) u[3 * i + c] += dt * (dw[c] + uxw[c]);
    }
}

/* twist off: u3 = M3_bar / C along the whole rod, from C u3' = (B1 - B2) u1 u2 = 0
 * (round section); a global tip moment is taken on the tip frame of step j */
static void quasi_static_twist(const rod_model *m, rod_state *s, const double moment[3])
{
    const int tip = m->nodes - 1;
    double twist_moment = moment[2];
    if (m->tip_frame == ROD_FRAME_GLOBAL) {
        double local[3];
        m3_mul_tv(local, &s->frame[9 * tip], moment);
        twist_moment = local[2];
    }
    for (int i = 0; i < tip; i++) s->darboux[3 * i + 2] = twist_moment / m->stiffness[2];
}

/* 2. (4.6)-(4.8) frames from the clamp: Q(i+1) = Q(i) R(u(i)); Q(0) stays clamped */
static void march_frames(const rod_model *m, rod_state *s)
{
    double *q = s->frame;
    for (int i = 0; i < m->nodes - 1; i++) {
        double rot[9];
        segment_rotation(rot, &s->darboux[3 * i], m->ds, m->options.exact_rotation);
        m3_mul(&q[9 * (i + 1)], &q[9 * i], rot);
    }
}

/* tip loads at t + dt (4.2): N_bar, u(NS) = B^-1 M_bar, director components */
static void tip_conditions(const rod_model *m, rod_state *s, const double force[3],
                           const double moment[3], double tip_force[3])
{
    const int tip = m->nodes - 1;
    double tip_moment[3];
    if (m->tip_frame == ROD_FRAME_GLOBAL) {
        m3_mul_tv(tip_force, &s->frame[9 * tip], force);
        m3_mul_tv(tip_moment, &s->frame[9 * tip], moment);
    } else {
        v3_copy(tip_force, force);
        v3_copy(tip_moment, moment);
    }
    for (int c = 0; c < 3; c++) s->darboux[3 * tip + c] = tip_moment[c] / m->stiffness[c];
}

/* 3. (4.12) I omega(j+1) = I omega(j) + dt (d3 x N(j) + L - omega x I omega
 *                                          + B u'(j+1) + u x B u (j+1)) */
static void update_angular_velocity(const rod_model *m, const rod_state *s, double dt,
                                    int components, double *wn)
{
    const int ns = m->nodes, tip = ns - 1;
    const double ds = m->ds;
    const double *inertia = m->rotary_inertia, *stiffness = m->stiffness;
    const double *u = s->darboux, *om = s->angular_velocity, *nf = s->contact_force;
    v3_set(&wn[0], 0.0, 0.0, 0.0);
    for (int i = 1; i < ns; i++) {
        const double *ui = &u[3 * i], *wi = &om[3 * i];
        double du[3], bu[3], iw[3], d3xn[3], wxiw[3], uxbu[3];
        if (i == tip) { /* one-sided at the free end */
            v3_sub(du, &u[3 * tip], &u[3 * (tip - 1)]);
            v3_scale(du, du, 1.0 / ds);
        } else {
            v3_sub(du, &u[3 * (i + 1)], &u[3 * (i - 1)]);
            v3_scale(du, du, 0.5 / ds);
        }
        for (int c = 0; c < 3; c++) {
            bu[c] = stiffness[c] * ui[c];
            iw[c] = inertia[c] * wi[c];
        }
        v3_cross(d3xn, E3, &nf[3 * i]);
        v3_cross(wxiw, wi, iw);
        v3_cross(uxbu, ui, bu);
        for (int c = 0; c < components; c++) {
            double torque = d3xn[c] - m->angular_damping * wi[c] - wxiw[c] +
                            stiffness[c] * du[c] + uxbu[c];
            wn[3 * i + c] = wi[c] + dt * torque / inertia[c];
        }
    }
}

/* twist off, (4.5)_3: omega3' = u3_t - (u x omega)_3, trapezoidal march from
 * omega3(0) = 0 */
static void quasi_static_spin(const rod_model *m, const rod_state *s, double dt,
                              double old_twist, double *wn)
{
    const int ns = m->nodes, tip = ns - 1;
    const double *u = s->darboux;
    double twist_rate = (u[3 * tip + 2] - old_twist) / dt;
    double g_prev = twist_rate; /* at the clamp omega = 0 */
    wn[2] = 0.0;
    for (int i = 1; i < ns; i++) {
        double g = twist_rate - (u[3 * i] * wn[3 * i + 1] - u[3 * i + 1] * wn[3 * i]);
        wn[3 * i + 2] = wn[3 * (i - 1) + 2] + 0.5 * m->ds * (g_prev + g);
        g_prev = g;
    }
}

/* 4. (4.10) v(i+1) = v(i-1) + 2 ds (omega x d3 - u x v)(i), from v(0) = 0 */
static void march_velocity(const rod_model *m, rod_state *s)
{
    const int tip = m->nodes - 1;
    const double ds = m->ds;
    const double *u = s->darboux, *om = s->angular_velocity;
    double *v = s->velocity;
    v3_set(&v[0], 0.0, 0.0, 0.0);
    {
        /* trapezoidal start: v1 + ds/2 u1 x v1 = ds/2 (omega0 x d3 + omega1 x d3 - u0 x v0) */
        double a[3], b[3], w0[3], w1[3];
        v3_cross(w0, &om[0], E3);
        v3_cross(w1, &om[3], E3);
        v3_add(b, w0, w1);
        v3_scale(b, b, 0.5 * ds);
        v3_scale(a, &u[3], 0.5 * ds);
        solve_plus_cross(&v[3], a, b);
    }
    for (int i = 1; i < tip; i++) {
        double wxd3[3], uxv[3];
        v3_cross(wxd3, &om[3 * i], E3);
        v3_cross(uxv, &u[3 * i], &v[3 * i]);
        for (int c = 0; c < 3; c++)
            v[3 * (i + 1) + c] = v[3 * (i - 1) + c] + 2.0 * ds * (wxd3[c] - uxv[c]);
    }
}

/* g(i) of (4.14) without the -u x N term: m v-dot + m omega x v - distributed + c v */
static void force_rate(double h[3], const rod_model *m, const rod_state *s, const double *vo,
                       double dt, int i)
{
    const double mass = m->mass_per_length;
    const double *v = s->velocity;
    double wxv[3], dist[3];
    v3_cross(wxv, &s->angular_velocity[3 * i], &v[3 * i]);
    m3_mul_tv(dist, &s->frame[9 * i], m->distributed_force);
    for (int c = 0; c < 3; c++)
        h[c] = mass * (v[3 * i + c] - vo[3 * i + c]) / dt + mass * wxv[c] - dist[c] +
               m->linear_damping * v[3 * i + c];
}

/* 5. (4.14) from the free end: N(i-1) = N(i+1) - 2 ds g(i),
 *    g = m v-dot + m omega x v - u x N - T, T = distributed - c v (director) */
static void march_internal_force(const rod_model *m, rod_state *s, const double *vo, double dt,
                                 const double tip_force[3])
{
    const int tip = m->nodes - 1;
    const double ds = m->ds;
    const double *u = s->darboux;
    double *nf = s->contact_force;
    v3_copy(&nf[3 * tip], tip_force);
    for (int i = tip; i >= 1; i--) {
        double h[3];
        force_rate(h, m, s, vo, dt, i);
        if (i == tip) {
            /* trapezoidal start: N(tip-1) = N(tip) - ds/2 (g(tip) + g(tip-1)),
               g(tip-1) contains -u x N(tip-1): (I - ds/2 [u]x) N = rhs */
            double uxn[3], hp[3], rhs[3], a[3];
            const int p = tip - 1;
            v3_cross(uxn, &u[3 * tip], &nf[3 * tip]);
            force_rate(hp, m, s, vo, dt, p);
            for (int c = 0; c < 3; c++)
                rhs[c] = nf[3 * tip + c] - 0.5 * ds * (h[c] - uxn[c] + hp[c]);
            v3_scale(a, &u[3 * p], -0.5 * ds);
            solve_plus_cross(&nf[3 * p], a, rhs);
            continue;
        }
        double uxn[3];
        v3_cross(uxn, &u[3 * i], &nf[3 * i]);
        for (int c = 0; c < 3; c++)
            nf[3 * (i - 1) + c] = nf[3 * (i + 1) + c] - 2.0 * ds * (h[c] - uxn[c]);
    }
}

/* 6. (4.16) R(i+1) = R(i-1) + 2 ds d3(i); R(0) clamped; trapezoidal start */
static void march_centreline(const rod_model *m, rod_state *s)
{
    const int tip = m->nodes - 1;
    const double ds = m->ds;
    const double *q = s->frame;
    double *r = s->position;
    double d0[3], d1[3];
    m3_column(d0, &q[0], 2);
    m3_column(d1, &q[9], 2);
    for (int c = 0; c < 3; c++) r[3 + c] = r[c] + 0.5 * ds * (d0[c] + d1[c]);
    for (int i = 1; i < tip; i++) {
        double d3[3];
        m3_column(d3, &q[9 * i], 2);
        for (int c = 0; c < 3; c++) r[3 * (i + 1) + c] = r[3 * (i - 1) + c] + 2.0 * ds * d3[c];
    }
}

/* A segment stretched beyond what the resolution explains: the start of (4.16), R(1) =
 * R(0) + ds/2 (d3(0) + d3(1)), makes segment 2 ds sqrt(5/2 - 3/2 cos(|u| ds)) long; twice
 * that is allowed (validation runs at NS = 11 with ML/EI = 2 pi reach 13 %), while |u| ds
 * stays below MAX_TURN (beyond it the frame march (4.7) does not resolve the bend).
 * Returns ROD_OK when the stretch is within bounds. */
static rod_status check_stretch(const rod_model *m, const thesis_work *w, const rod_state *s,
                                double max_u, rod_report *report)
{
    const double ds = m->ds;
    char what[400];
    int segment = 0;
    double stretch = worst_stretch(m, s, &segment);
    double turn = max_u * ds;
    double explained = sqrt(2.5 - 1.5 * cos(fmin(turn, MAX_TURN))) - 1.0;
    double stretch_limit = fmax(STRETCH_LIMIT, 2.0 * explained);
    if (!(stretch > stretch_limit || (turn > MAX_TURN && stretch > STRETCH_LIMIT))) return ROD_OK;
    /* segments 1-based, as a person counts them along the rod from the clamp */
    double d[3];
    v3_sub(d, &s->position[3 * (segment + 1)], &s->position[3 * segment]);
    snprintf(what, sizeof what,
             "segment %d of %d is %.3gx its rest length ds = %.3g m (limit %.3g %%: the "
             "centreline (4.16) follows d3, so a stretch means d3 zig-zags from node to node "
             "or the curvature is not resolved, |u| ds = %.2g rad, resolved up to %g)",
             segment + 1, m->nodes - 1, v3_norm(d) / ds, ds,
             100.0 * (turn > MAX_TURN ? STRETCH_LIMIT : stretch_limit), turn, MAX_TURN);
    /* below the threshold scale or above the predicted dt: the stretch is that
       limit's divergence, and its advice (scale, dt) is what works */
    double limit_dt = thesis_limit(m, m->rotary_inertia_scale, NULL);
    if (!(limit_dt > 0.0) || w->largest_dt > limit_dt)
        return unstable(m, w, s, report, what, NULL);
    /* the start of (4.16), R(1) = R(0) + ds/2 (d3(0) + d3(1)), alone makes segment 2
       ds sqrt(1 + 3/4 (|u| ds)^2): 1 % at |u| ds = 0.16 rad */
    rod_status st = unstable(m, w, s, report, what,
                             "more nodes (the error grows as (|u| ds)^2), a smaller dt, or "
                             "scheme = implicit (segments exactly ds by construction).");
    report->suggested_dt = 0.0; /* neither dt nor scale alone is known to cure it */
    report->suggested_scale = 0.0;
    return st;
}

/* divergence: non-finite, curvature beyond the rod's own radius, stretch, or growth */
static rod_status check_divergence(const rod_model *m, thesis_work *w, const rod_state *s,
                                   rod_report *report)
{
    const int ns = m->nodes;
    double max_omega = max_norm(s->angular_velocity, ns), max_u = max_norm(s->darboux, ns);
    char what[400];
    if (!isfinite(max_omega) || !isfinite(max_u) || !isfinite(max_norm(s->contact_force, ns)) ||
        !isfinite(max_norm(s->velocity, ns))) {
        snprintf(what, sizeof what,
                 "the state became non-finite (max |omega| had grown by a factor %.3g in the "
                 "step before)", w->last_growth);
        return unstable(m, w, s, report, what, NULL);
    }
    if (max_u > 2.0 / m->diameter) {
        snprintf(what, sizeof what,
                 "max |u| = %.3g 1/m exceeds 2/d = %.3g 1/m (a bend tighter than the rod's radius)",
                 max_u, 2.0 / m->diameter);
        return unstable(m, w, s, report, what, NULL);
    }
    rod_status st = check_stretch(m, w, s, max_u, report);
    if (st != ROD_OK) return st;
    double growth = w->previous_max_omega > 0.0 ? max_omega / w->previous_max_omega : 0.0;
    w->growth_count = growth > GROWTH_FACTOR ? w->growth_count + 1 : 0;
    w->last_growth = growth;
    w->previous_max_omega = max_omega;
    if (w->growth_count >= GROWTH_STEPS) {
        snprintf(what, sizeof what,
                 "max |omega| grew by a factor %.3g in the last step (%d steps in a row above %g)",
                 growth, GROWTH_STEPS, GROWTH_FACTOR);
        return unstable(m, w, s, report, what, NULL);
    }
    return ROD_OK;
}

/* One step of chapter 4: curvature, frames, tip conditions, spin, velocity, internal
 * force and centreline, each marched along the rod, then the divergence checks. */
static rod_status step(void *work, const rod_model *m, rod_state *s, double dt, rod_report *report)
{
    thesis_work *w = work;
    const int tip = m->nodes - 1;
    rod_status st = begin_step(w, s, dt, report);
    if (st != ROD_OK) return st;

    memcpy(w->old_velocity, s->velocity, (size_t)m->nodes * 3 * sizeof(double));
    const int twist_on = m->physics.twist;
    const int components = twist_on ? 3 : 2; /* twist off: u3, omega3 from equilibrium below */
    const double old_twist = s->darboux[3 * tip + 2]; /* u3^j: uniform when quasi-static */

    update_curvature(m, s, dt, components); /* (4.5) */
    double t_new = s->time + dt;
    double force[3], moment[3], tip_force[3];
    rod_tip_load(m, t_new, force, moment);
    if (!twist_on) quasi_static_twist(m, s, moment);
    march_frames(m, s);                           /* (4.6)-(4.8) */
    tip_conditions(m, s, force, moment, tip_force); /* (4.2) */
    update_angular_velocity(m, s, dt, components, w->new_omega); /* (4.12) */
    if (!twist_on) quasi_static_spin(m, s, dt, old_twist, w->new_omega);
    memcpy(s->angular_velocity, w->new_omega, (size_t)m->nodes * 3 * sizeof(double));
    march_velocity(m, s);                                       /* (4.10) */
    march_internal_force(m, s, w->old_velocity, dt, tip_force); /* (4.14) */
    march_centreline(m, s);                                     /* (4.16) */
    s->time = t_new;
    return check_divergence(m, w, s, report);
}

const rod_scheme_ops rod_scheme_thesis = {"thesis", create, step, destroy, stable_dt, NULL};
