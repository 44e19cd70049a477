/* newton.c: Newton's iteration on one step of the implicit scheme, its line
 * search and when it renews the Jacobian (newton.h). */
#include "sim/implicit/newton.h"

#include <math.h>
#include <string.h>

#include "sim/implicit/jacobian.h"
#include "sim/implicit/residual.h"

/* Newton iterations over which a step with contact must halve its residual,
 * else it is split at once rather than after newton_max_iterations: a stall
 * at friction's turn between stick and slip seldom ends, and the half steps
 * mostly converge (docs/decisions/0019-contact-jacobian-renewal.md) */
#define CONTACT_STALL 6
/* While self-contact pairs touch, the line search keeps a trial point whose
 * residual is below the largest of the iterate's and the last
 * PAIRS_NONMONOTONE iterates' (a non-monotone line search: Grippo,
 * Lampariello and Lucidi, SIAM J. Numer. Anal. 23, 1986): a full step that
 * moves a pair across friction's corner overshoots in that pair's residual
 * for one iteration, and a monotone search cut it to nothing
 * (docs/decisions/0030-nonmonotone-line-search.md) */
#define PAIRS_NONMONOTONE 3
/* ... and, with no surface or puncture in contact, below PAIRS_OVERSHOOT
 * times that largest: while pairs part or cross friction's corner, Newton's
 * whole step overshoots in their residual for an iteration or two, and with
 * the bar at 1 the search cut such steps to 1/8-1/64, iteration after
 * iteration, until CONTACT_STALL split the step (a loose knot dragged at
 * 1 kHz: 84 steps of 20-33 iterations in 10 s, 16 failed lines; with 10,
 * none failed, and fewer iterations than with no search at all). A step
 * whose residual does not halve is still split (CONTACT_STALL), and the
 * step ends only at the tolerance. Not with surfaces or punctures, whose
 * smooth laws want the search: without it a surgeon's knot at 5 ms steps
 * did not converge down to dt/4096, and with 10 a knot tied by instruments
 * on a pad (instrument_tie.ini) needed 55 patient steps and 28 % more CPU
 * (docs/decisions/0103-live-knot-newton.md) */
#define PAIRS_OVERSHOOT 10.0
/* With strands touching, a step that took at least PAIRS_SLOW_STEP Newton
 * iterations on a B made PAIRS_B_AGE or more steps before renews B at the
 * next step's first iterate: a knot slides through the rod as it tightens,
 * and a B made where it was some steps ago is off where the strands now
 * press (docs/decisions/0031-b-renewal-policy.md) */
#define PAIRS_SLOW_STEP 3
#define PAIRS_B_AGE 10
/* A slow iteration with strands touching whose full step left the scheme's
 * own residual below PAIRS_ROD_SOLVED of the iterate's, on a B made 1 to
 * PAIRS_B_AGE - 1 steps before, keeps B: B solved the rod, and the
 * slowness is the pairs' overshoot (the line search then cut the step). A
 * coil lying on itself (NS = 201) renewed B every 2 to 4 steps so, 0.22
 * Jacobians a step, with no fewer iterations for it; a B made at this
 * step, or older, is renewed as before (a tight knot's iterations rose by
 * a fifth without those renewals: docs/decisions/0109-self-contact-idle.md) */
#define PAIRS_ROD_SOLVED 0.01
/* A chord iteration that leaves the residual above the tolerance, having
 * contracted it by less than this, marks the factorisation stale, for the
 * next step to renew at its first iterate, or implicit_refresh between
 * steps in live mode: the contraction worsens slowly over tens of steps,
 * and a renewal at its first signs spares the builds within a step
 * (docs/decisions/0019-contact-jacobian-renewal.md) */
#define IDLE_REFRESH_CONTRACTION 0.1
/* A step that starts on a factorisation the last one found stale renews
 * only contact's part of it (onto the rod's part kept from the last whole
 * build) up to this many times in a row, then the whole: at a suture's
 * short steps the thread's own Jacobian barely changes from one step to the
 * next, while which nodes touch, stick or slip does
 * (docs/decisions/0019-contact-jacobian-renewal.md) */
#define CONTACT_START_REFRESHES 4
/* A chord iteration with contact (surfaces, punctures) and no strands
 * touching that contracts the residual by less than this renews the
 * Jacobian (contact's part first); 0.25 elsewhere. A renewal of contact's
 * part costs about two residual evaluations, and each iteration it spares
 * saves one and a solve (docs/decisions/0019-contact-jacobian-renewal.md) */
#define CONTACT_SLOW_CONTRACTION 0.05

int implicit_same_dt(double dt_factored, double dt)
{
    return fabs(dt - dt_factored) <= 1e-9 * fabs(dt);
}

/* self-contact's solve of B v = e for count columns given by their entries
 * (rod_self_contact_solve) */
static void solve_entries(const void *ctx, double *b, int count, int first, const int *start,
                          const int *row, const double *value)
{
    band_solve_entries(ctx, b, count, first, start, row, value);
}

/* Newton's correction dx = J^-1 r: the banded factors, and the self-contact
 * forces (unknowns beside x) by the Schur complement on them
 * (sim/contact/self_contact.h). */
static void newton_solve(implicit_work *w, const rod_model *m, double dt)
{
    band_solve(&w->lu, w->dx);
    if (w->self && w->self->count)
        rod_self_contact_correct(w->self, w->dx, w->node_push, m->options.theta * dt / m->ds,
                                 solve_entries, &w->lu);
}

/* N: what the self-contact pairs' residual is measured against, the force
 * scale or the largest force a pair's law asks for at the last evaluation,
 * if more (a strand pressed hard is held to the tolerance relative to its
 * force, as the difference quotients of its law allow) */
static double pair_scale(const implicit_work *w)
{
    return w->self && w->self->count ? fmax(w->force_scale, w->self->fmax) : w->force_scale;
}

/* The size of a residual whose scheme's part (scaled) is rod: the larger
 * of it and the pairs' (over scale, N); NaN when either is (fmax drops a
 * NaN: a residual gone NaN beside small pairs' was taken for converged) */
static double norm_with_pairs(const implicit_work *w, double rod, double scale)
{
    if (!(w->self && w->self->count)) return rod;
    const double pairs = w->self->gnorm / scale;
    return isnan(rod) || isnan(pairs) ? NAN : fmax(rod, pairs);
}

/* The size of the residual: the scheme's (scaled) and the pairs' (over
 * scale, N) */
static double residual_norm_at(const implicit_work *w, double scale)
{
    return norm_with_pairs(w, implicit_max_abs(w->residual, w->unknowns), scale);
}

/* A fingerprint of which self-contact pairs are active (their laws ask for
 * a force or they hold one) at the last evaluation */
static unsigned long active_pairs(const implicit_work *w)
{
    unsigned long h = 1469598103934665603ul;
    if (w->self)
        for (int q = 0; q < w->self->count; q++)
            if (w->self->pair[q].active) h = (h ^ (unsigned long)(q + 1)) * 1099511628211ul;
    return h;
}

/* What Newton carries from one iteration of a step to the next */
typedef struct newton_progress {
    double scale;          /* N: the pairs' residual scale (pair_scale). Within one
                              iteration the line search compares the residual before and
                              after on one scale, that of the iterate it starts from: with
                              each trial point's own, a trial that raised some pair's force
                              looked better than it was, and the search turned back from
                              good steps (0030-nonmonotone-line-search.md) */
    double norm;           /* the residual's size at the iterate */
    int fresh;             /* the factorisation was made at this step */
    int contact_fresh;     /* the contact's part was renewed at the last iteration */
    int rebuilt;           /* whole Jacobians built at slow iterations of this attempt */
    double history[CONTACT_STALL];    /* the residual's size at the last iterations */
    double recent[PAIRS_NONMONOTONE]; /* the same, for the line search */
    int rod_leads, rod_led; /* the scheme's residual the larger at the last iterates */
} newton_progress;

/* The factorisation a step starts on: contact's part renewed at the first
 * iterate when the last step found it stale (CONTACT_START_REFRESHES), a
 * whole one when there is none for this dt or the strands asked for a new B
 * (PAIRS_SLOW_STEP). Returns 0, or -1 when the matrix is singular. */
static int start_factorisation(implicit_work *w, const rod_model *m, double t, double dt)
{
    const long before = w->jacobian_builds;
    int why = BUILD_WHY;
    if (w->stale_start && w->has_contact && !w->contact_fd && !w->fd_only &&
        w->smooth_kl == w->lu.kl && implicit_same_dt(w->smooth_dt, dt) &&
        w->smooth_renewals < CONTACT_START_REFRESHES) {
        why = BUILD_STALE_CONTACT;
        if (implicit_refresh_contact_jacobian(w, m, t, dt)) return -1;
        w->smooth_renewals++;
        w->stale = 0;
    } else if (!w->have_factor || !implicit_same_dt(w->jacobian_dt, dt) ||
               (w->renew_pairs && w->self && w->self->count)) {
        why = w->stale_start          ? BUILD_STALE_WHOLE
              : w->jacobian_builds == 0 ? BUILD_FIRST
              : !w->have_factor       ? BUILD_LOST
              : !implicit_same_dt(w->jacobian_dt, dt) ? BUILD_DT
                                                    : BUILD_PAIRS;
        if (implicit_factor_jacobian(w, m, t, dt)) return -1;
    }
    if (why < BUILD_WHY) w->builds_by[why] += w->jacobian_builds - before;
    w->renew_pairs = 0;
    w->stale_start = 0;
    return 0;
}

/* What a trial point must beat at iteration it: the iterate's residual, or
 * with pairs touching the largest of it and the last PAIRS_NONMONOTONE,
 * times PAIRS_OVERSHOOT when nothing else touches (contact: surfaces or
 * punctures in the residual) */
static double line_search_bar(newton_progress *pr, int it, int self_touch, int contact)
{
    double bar = pr->norm;
    if (self_touch)
        for (int j = 1; j <= PAIRS_NONMONOTONE && j <= it; j++)
            bar = fmax(bar, pr->recent[(it - j) % PAIRS_NONMONOTONE]);
    pr->recent[it % PAIRS_NONMONOTONE] = pr->norm;
    return self_touch && !contact ? PAIRS_OVERSHOOT * bar : bar;
}

/* Contact makes the residual piecewise smooth: a full step can jump across
 * contacts that switch on or off, so back along it (halving, at most 8
 * times) until the residual falls below bar. *next: the residual's size at
 * the point kept, *rod: the scheme's own part of it (scaled); returns the
 * fraction of the step kept, or -1 when the step's budget runs out. */
static double line_search(implicit_work *w, const rod_model *m, double t, double dt, double bar,
                          double scale, double *next, double *rod)
{
    const int nu = w->unknowns;
    double step = 1.0;
    for (int k = 0; k < 8 && !(*next < bar); k++) {
        step *= 0.5;
        for (int i = 0; i < nu; i++) w->x[i] += step * w->dx[i];
        if (w->self) rod_self_contact_move(w->self, step);
        implicit_evaluate_iterate(w, m, t, dt);
        *rod = implicit_max_abs(w->residual, nu);
        *next = norm_with_pairs(w, *rod, scale);
        if (--w->budget < 0) return -1.0;
    }
    return step;
}

/* After an iteration that contracted the residual from pr->norm to next
 * (the fraction cut of the step kept; rod_full the scheme's own residual at
 * the full step, rod_now at the point kept): a Jacobian renewed when the
 * iteration was slow for a reason a new one mends. Not when only the
 * self-contact pairs' residual was slow, or a pair switched on or off, or
 * the line search cut a step whose scheme's residual had fallen well: their
 * laws are linearised afresh at every iteration and B holds none of them.
 * With contact, its part first (cheap); the whole when that did not help at
 * the last iteration, twice at most (a thread turning as it lands needs the
 * rod's part renewed; slowness beyond that is friction's turn between stick
 * and slip, which the rod's part does not change)
 * (docs/decisions/0031-b-renewal-policy.md, 0019-contact-jacobian-renewal.md).
 * Returns 0, or -1 when the matrix is singular. */
static int renew_if_slow(implicit_work *w, const rod_model *m, double t, double dt,
                         newton_progress *pr, double next, double cut, double rod_full,
                         double rod_now, unsigned long active_before, int self_touch)
{
    const double norm = pr->norm, tol = m->options.newton_tolerance;
    const int cut_alone = cut < 1.0 && rod_full <= 0.25 * norm &&
                          next <= (1.0 - 0.9 * cut) * norm;
    const int pairs_alone = self_touch && (rod_now <= 0.25 * norm ||
                                           active_pairs(w) != active_before || cut_alone ||
                                           (rod_full <= PAIRS_ROD_SOLVED * norm &&
                                            w->self->b_age >= 1 &&
                                            w->self->b_age < PAIRS_B_AGE));
    const double slow = w->has_contact && !self_touch ? CONTACT_SLOW_CONTRACTION : 0.25;
    /* slow, and not merely at the round-off floor near the tolerance */
    if (next > slow * norm && next > 10.0 * tol && !pairs_alone &&
        (!pr->fresh || w->has_contact || (self_touch && pr->rebuilt < 2))) {
        const long before = w->jacobian_builds;
        if (w->has_contact && !w->contact_fd && (!pr->contact_fresh || pr->rebuilt >= 2)) {
            if (implicit_refresh_contact_jacobian(w, m, t, dt)) return -1;
            pr->contact_fresh = 1;
            w->builds_by[BUILD_SLOW_CONTACT] += w->jacobian_builds - before;
        } else {
            if (implicit_factor_jacobian(w, m, t, dt)) return -1;
            pr->fresh = 1;
            pr->rebuilt++;
            w->builds_by[BUILD_SLOW_WHOLE] += w->jacobian_builds - before;
        }
    } else {
        pr->contact_fresh = 0;
    }
    return 0;
}

/* One iteration from the iterate x (its residual evaluated, of size
 * pr->norm): the correction, the line search, the Jacobian's renewal.
 * Returns 0, or -1 when the step fails (budget, a non-finite residual, a
 * singular matrix). */
static int newton_iteration(implicit_work *w, const rod_model *m, double t, double dt, int it,
                            newton_progress *pr)
{
    const int nu = w->unknowns;
    const double tol = m->options.newton_tolerance;
    memcpy(w->dx, w->residual, (size_t)nu * sizeof(double));
    const unsigned long active_before = active_pairs(w);
    newton_solve(w, m, dt);
    for (int i = 0; i < nu; i++) w->x[i] -= w->dx[i];
    if (w->self) rod_self_contact_move(w->self, -1.0);
    implicit_evaluate_iterate(w, m, t, dt);
    /* the scheme's own residual at the full step (renew_if_slow), measured
     * once: it gives the residual's size, and rod_now unless the line
     * search moves the iterate */
    const double rod_at_full = implicit_max_abs(w->residual, nu);
    double next = norm_with_pairs(w, rod_at_full, pr->scale);
    const int self_touch = w->self && w->self->count;
    const double rod_full = self_touch ? rod_at_full : 0.0;
    double cut = 1.0; /* the fraction of the step the line search kept */
    const int contact = w->has_contact || self_touch;
    const double bar = line_search_bar(pr, it, self_touch, w->has_contact);
    /* the scheme's own residual at the point kept */
    double rod_now = rod_at_full;
    if (contact && !(next < bar)) {
        cut = line_search(w, m, t, dt, bar, pr->scale, &next, &rod_now);
        if (cut < 0.0) return -1;
    }
    if (!isfinite(next)) return -1;
    /* the iterate before this one left the scheme's residual above the
     * pairs' (PAIRS_SLOW_STEP) */
    pr->rod_led = pr->rod_leads;
    pr->rod_leads = self_touch && rod_now >= w->self->gnorm / pr->scale;
    /* the new iterate's own scale, taken before a rebuild below
     * (whose finite differences leave the pairs' laws unevaluated) */
    pr->scale = pair_scale(w);
    const double next_norm = norm_with_pairs(w, rod_now, pr->scale);
    if (next > IDLE_REFRESH_CONTRACTION * pr->norm && next > tol) w->stale = 1;
    if (renew_if_slow(w, m, t, dt, pr, next, cut, rod_full, rod_now, active_before, self_touch))
        return -1;
    pr->norm = next_norm;
    return 0;
}

/* With contact or pairs touching: 1 when the residual has not halved over
 * the last CONTACT_STALL iterations (the step is split at once); a patient
 * attempt goes on, noting it did (patience_used) */
static int stalled(implicit_work *w, const rod_model *m, int it, newton_progress *pr)
{
    if (!((w->has_contact && !w->contact_fd) || (w->self && w->self->count))) return 0;
    if (it >= CONTACT_STALL && pr->norm > m->options.newton_tolerance &&
        !(pr->norm <= 0.5 * pr->history[it % CONTACT_STALL])) {
        if (!w->patient) return 1;
        w->patience_used = 1;
    }
    pr->history[it % CONTACT_STALL] = pr->norm;
    return 0;
}

int implicit_newton(implicit_work *w, const rod_model *m, double t, double dt, rod_report *report)
{
    const double tol = m->options.newton_tolerance;
    const int max_it = (w->patient ? PATIENT_FACTOR : 1) * m->options.newton_max_iterations;
    if (start_factorisation(w, m, t, dt)) return -1;
    implicit_evaluate_iterate_once(w, m, t, dt);
    newton_progress pr = {.fresh = 0};
    pr.scale = pair_scale(w);
    pr.norm = residual_norm_at(w, pr.scale);
    for (int it = 0; it < max_it; it++) {
        report->newton_iterations = it;
        if (pr.norm <= tol) {
            /* slow on an old B with strands touching (PAIRS_SLOW_STEP) */
            w->renew_pairs = w->self && w->self->count && it >= PAIRS_SLOW_STEP &&
                             w->self->b_age >= PAIRS_B_AGE && pr.rod_led;
            return 0;
        }
        if (--w->budget < 0) return -1;
        if (it >= m->options.newton_max_iterations) w->patience_used = 1;
        w->newton_total++;
        if (newton_iteration(w, m, t, dt, it, &pr)) return -1;
        if (stalled(w, m, it, &pr)) return -1;
    }
    report->newton_iterations = max_it;
    return pr.norm <= tol ? 0 : -1;
}
