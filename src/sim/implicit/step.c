/* step.c: the implicit scheme's step: one attempt (single_step, a short
 * list of named stages), its splitting into halves when Newton fails, the
 * depth a run of steps starts split at, the retries, and the message of a
 * step that cannot be solved (step.h). */
#include "sim/implicit/step.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/surface.h"
#include "sim/implicit/accept.h"
#include "sim/implicit/jacobian.h"
#include "sim/implicit/newton.h"
#include "sim/implicit/start.h"
#include "sim/rod.h"
#include "sim/rod_geometry.h"
#include "sim/rod_grid.h"

#define MAX_SPLIT_DEPTH 12
/* With self-contact, a step some attempt of which moved the strands too
 * far for the no-pass-through test starts the next steps already split to
 * one level below the deepest such attempt; after SPLIT_HOLD_STEPS steps
 * with no such attempt, one level coarser again: a loose knot swinging as
 * it is pulled tight moves too far within the scene's step at most of its
 * steps, and there the halves' depth changes slowly. Each sub-step still
 * meets the same tolerance and the same test
 * (docs/decisions/0032-split-hold-steps.md). */
#define SPLIT_HOLD_STEPS 4
/* Newton iterations one step may spend, splits included (each attempt costs
 * one more; with contact twice: the retries): bounds the time a hopeless
 * step takes instead of 4096 x 25 tries. Every loop of the scheme is
 * bounded: Newton by newton_max_iterations and this budget, splitting by
 * MAX_SPLIT_DEPTH and this budget, the rest by the node count
 * (docs/decisions/0020-stalled-step-splits.md) */
#define STEP_ITERATION_BUDGET 4000
/* After a step that needed patience (PATIENT_FACTOR: the last retry
 * solved it, or a held step went past the stall test), this many steps
 * start patient, without the failed tries first: such steps come in runs (a
 * strand settling onto another on a floor), and the failed tries of one
 * cost about 20 steps' time (docs/decisions/0072-pile-planar.md) */
#define PATIENT_HOLD_STEPS 4
/* The last resort's budget, in steps' budgets (step_budget): started from
 * the last solution, a knot's sub-steps of dt/64 - dt/128 converge but
 * slowly (the surgeon's knot by instruments at strand friction 0.3:
 * 25 - 40 iterations each), and one budget ran out 0.9 ms into the step
 * (docs/decisions/0135-stall-fallback.md); not with a caller's own
 * budget (rod_options.iteration_budget) */
#define RESORT_BUDGET_FACTOR 4

/* The Newton iterations one try of a step may spend: the caller's
 * rod_options.iteration_budget when > 0 (rodsim live bounds each line),
 * else STEP_ITERATION_BUDGET. */
static int step_budget(const rod_model *m)
{
    return m->options.iteration_budget > 0 ? m->options.iteration_budget : STEP_ITERATION_BUDGET;
}

static void save_state(implicit_work *w, const rod_state *s)
{
    size_t n = (size_t)w->nodes;
    memcpy(w->save_frame, s->frame, n * 9 * sizeof(double));
    memcpy(w->save_pos, s->position, n * 3 * sizeof(double));
    memcpy(w->save_vel, s->velocity, n * 3 * sizeof(double));
    memcpy(w->save_omega, s->angular_velocity, n * 3 * sizeof(double));
    memcpy(w->save_force, s->contact_force, n * 3 * sizeof(double));
    /* the punctures in use: those past the count are zero (each made
     * zeroed, none removed; restore_state zeroes those a try made) */
    memcpy(w->save_puncture, s->puncture, (size_t)s->puncture_count * sizeof *s->puncture);
    w->save_puncture_count = s->puncture_count;
    memcpy(w->save_grasp, s->grasp, sizeof s->grasp);
    memcpy(w->save_grasp_log, s->grasp_log, sizeof s->grasp_log);
    w->save_grasp_log_count = s->grasp_log_count;
    w->save_cut_request = s->cut_request;
    w->save_time = s->time;
}

static void restore_state(const implicit_work *w, rod_state *s)
{
    size_t n = (size_t)w->nodes;
    memcpy(s->frame, w->save_frame, n * 9 * sizeof(double));
    memcpy(s->position, w->save_pos, n * 3 * sizeof(double));
    memcpy(s->velocity, w->save_vel, n * 3 * sizeof(double));
    memcpy(s->angular_velocity, w->save_omega, n * 3 * sizeof(double));
    memcpy(s->contact_force, w->save_force, n * 3 * sizeof(double));
    const int kept = w->save_puncture_count, made = s->puncture_count;
    memcpy(s->puncture, w->save_puncture, (size_t)kept * sizeof *s->puncture);
    if (made > kept) memset(&s->puncture[kept], 0, (size_t)(made - kept) * sizeof *s->puncture);
    s->puncture_count = kept;
    memcpy(s->grasp, w->save_grasp, sizeof s->grasp);
    memcpy(s->grasp_log, w->save_grasp_log, sizeof s->grasp_log);
    s->grasp_log_count = w->save_grasp_log_count;
    s->cut_request = w->save_cut_request;
    s->time = w->save_time;
}

/* m: the farthest a node moves over the step of the last residual
 * evaluation (r(t+dt) = r(t) + dt vbar) */
static double largest_motion(const implicit_work *w, double dt)
{
    double moved = 0.0;
    for (int i = 0; i < w->nodes; i++) moved = fmax(moved, dt * v3_norm(&w->vbar[3 * i]));
    return moved;
}

/* m: the farthest a node that could meet another strand within the step
 * moves (rod_self_contact_near_motion), when the farthest of all nodes
 * moves beyond what the candidates' margin covers; else that farthest. A
 * free end whipping at 3-6 m/s at the end of a 4 cm tail below a loose knot
 * split the knot's steps of its first 0.12 s 4-8 ways by its own motion
 * (docs/decisions/0103-live-knot-newton.md) */
static double strands_motion(implicit_work *w, double dt)
{
    const double moved = largest_motion(w, dt);
    if (!(2.0 * moved > w->self->margin)) return moved;
    return rod_self_contact_near_motion(w->self, w->pos0, w->vbar, dt, moved);
}

/* Notes that an attempt at this depth moved too far (SPLIT_HOLD_STEPS). */
static void moved_too_far(implicit_work *w)
{
    if (w->split_depth > w->motion_depth) w->motion_depth = w->split_depth;
}

/* No pass-through: every pair that could have met within the step must
 * have been a candidate. Points move by at most `moved`, so two segments
 * farther apart than one diameter + 2 moved at the start cannot touch on
 * the way; only nodes near another strand count (strands_motion); a step
 * that moved farther than the candidates' margin allowed is solved again
 * with a wider one. The margin stays within SELF_MARGIN
 * diameters: the pairs' contact is linearised about the start (the
 * half-space between the closest points), which stands for the strands
 * only near them, so a step that would need more is split, unless no
 * strand is near at all. Returns 0 (the pairs' forces kept), -1 (split the
 * step) or -2 (report->message set). */
static int strands_kept_apart(implicit_work *w, const rod_model *m, const rod_state *s,
                              double dt, rod_report *report)
{
    double moved = strands_motion(w, dt);
    int apart = 0; /* no pair could touch within the step */
    for (int tries = 0; tries < 4 && 2.0 * moved > w->self->margin; tries++) {
        const int fast = 3.0 * moved > SELF_MARGIN * m->diameter;
        if (fast || w->self->margin == 0.0) {
            /* nothing that could touch within the step: no candidates
             * needed (a straight stretch swinging fast moves its
             * nearby segments together: rod_self_contact_reachable); a
             * step without candidates (nothing was near) is kept so */
            apart = rod_self_contact_reachable(w->self, w->pos0, w->vbar, dt, 2.0 * moved) == 0;
            if (apart) break;
            if (fast) {
                moved_too_far(w);
                return -1;
            }
        }
        if (implicit_prepare_self_contact(w, m, dt, 3.0 * moved, report)) return -2;
        if (implicit_newton(w, m, s->time, dt, report)) return -1;
        moved = strands_motion(w, dt);
    }
    if (!apart && 2.0 * moved > w->self->margin && 3.0 * moved <= SELF_MARGIN * m->diameter) {
        moved_too_far(w);
        return -1; /* split the step */
    }
    w->self_motion = moved;
    rod_self_contact_accept(w->self);
    return 0;
}

/* One theta-method step without splitting. Returns 0, -1 (no convergence:
 * split it) or -2 (report->message set: no splitting helps). */
static int single_step(implicit_work *w, const rod_model *m, rod_state *s, double dt,
                       rod_report *report)
{
    int continuing, rc;
    if ((rc = implicit_prepare_step(w, m, s, dt, report, 1, &continuing))) return rc;
    if (implicit_newton(w, m, s->time, dt, report)) return -1;
    for (int i = 0; i < w->unknowns; i++)
        if (!isfinite(w->x[i])) return -1; /* never accept a non-finite solution */
    if (w->self && (rc = strands_kept_apart(w, m, s, dt, report))) return rc;
    return implicit_accept_step(w, m, s, dt, continuing, report);
}

/* The step of dt at split depth `depth`: one attempt, and when it fails its
 * two halves, recursively (MAX_SPLIT_DEPTH deep at most, within the
 * budget); no attempt at depths below start_depth (SPLIT_HOLD_STEPS).
 * Returns 0, -1 (not solved) or -2 (report->message set: no splitting
 * helps). */
static int split_step(implicit_work *w, const rod_model *m, rod_state *s, double dt,
                      rod_report *report, int depth)
{
    /* every attempt costs the budget at least one iteration, also one that
     * fails before Newton iterates (a singular Jacobian): the splits stay
     * bounded by the budget, not only by 2^MAX_SPLIT_DEPTH attempts, each
     * with a Jacobian build */
    if (--w->budget < 0) return -1;
    if (depth > w->deepest) w->deepest = depth;
    int rc = -1;
    if (depth >= w->start_depth) {
        w->split_depth = depth;
        rc = single_step(w, m, s, dt, report);
    } else {
        w->budget++; /* split without an attempt (SPLIT_HOLD_STEPS) */
    }
    if (rc == 0 || rc == -2) return rc; /* -2: no splitting helps (message set) */
    if (depth >= MAX_SPLIT_DEPTH || w->budget < 0) return -1;
    w->have_factor = 0;
    rc = split_step(w, m, s, 0.5 * dt, report, depth + 1);
    if (rc) return rc;
    w->have_factor = 0;
    return split_step(w, m, s, 0.5 * dt, report, depth + 1);
}

/* The depth the next steps start split at (SPLIT_HOLD_STEPS), after a step
 * whose first attempt solved it or not */
static void hold_split_depth(implicit_work *w, double dt, int solved)
{
    int next = w->start_depth;
    if (w->motion_depth >= 0) {
        next = w->motion_depth + 1;
        w->depth_streak = 0;
    } else if (next > 0 && ++w->depth_streak >= SPLIT_HOLD_STEPS) {
        next--;
        w->depth_streak = 0;
    }
    w->next_depth = !solved ? 0 : next < MAX_SPLIT_DEPTH ? next : MAX_SPLIT_DEPTH - 1;
    w->depth_dt = dt;
}

/* Counts a step that needed patience, in report's warning (its count
 * kept up to date; another warning that came first stays) */
static void note_patient(implicit_work *w, const rod_model *m, rod_report *report)
{
    static const char what[] = "implicit scheme: Newton's method was let run past its stall test";
    w->patient_steps++;
    if (w->patient_steps == 1) w->patient_first = w->save_time;
    if (report->warning[0] && strncmp(report->warning, what, sizeof what - 1) != 0) return;
    snprintf(report->warning, sizeof report->warning,
             "%s (up to %d iterations at the step's dt, not split when slow) at %ld step%s, the "
             "first at t = %.6g s (contact turning between stick and slip at most iterations)",
             what, PATIENT_FACTOR * m->options.newton_max_iterations, w->patient_steps, w->patient_steps == 1 ? "" : "s",
             w->patient_first);
}

/* With contact, a step that failed (split == -1) again, splits included,
 * with a budget of its own: first with the rod's part of the Jacobian by
 * finite differences and a first iterate off any symmetry, then the whole
 * Jacobian by differences, refreshed at every slow iteration. A straight
 * hanging thread lowered end-on onto a table has no solution that stays
 * straight, and the exact Jacobian, as symmetric as the thread, keeps
 * Newton on that line, its end pressed ever harder while the compliance
 * caps its sink (docs/decisions/0020-stalled-step-splits.md). Last, a
 * patient attempt (PATIENT_FACTOR): the exact Jacobian, Newton let run
 * past the stall test; it starts PATIENT_HOLD_STEPS patient steps, and it
 * and those of them that needed patience are counted in report's warning.
 * Only a step every earlier try failed gets here, so no run that converged
 * without it changes. Returns the last attempt's
 * split_step result. */
static int retry_with_differences(implicit_work *w, const rod_model *m, rod_state *s, double dt,
                                  rod_report *report, int split)
{
    for (int retry = 1; retry <= 3 && split == -1 && w->has_contact; retry++) {
        restore_state(w, s);
        w->fd_only = retry < 3;
        w->contact_fd = retry == 2;
        w->patient = retry == 3;
        w->have_factor = 0;
        w->budget = step_budget(m);
        split = split_step(w, m, s, dt, report, 0);
        if (split == 0 && w->patient) {
            note_patient(w, m, report);
            w->patient_hold = PATIENT_HOLD_STEPS;
        }
        w->patient = 0;
        w->contact_fd = 0;
        w->fd_only = 0;
        w->have_factor = 0;
    }
    return split;
}

/* The step's last resort, when every try above failed (split == -1) and
 * the run would end, with self-contact: the step again from its start,
 * splits included, with RESORT_BUDGET_FACTOR budgets of its own, the
 * exact Jacobian, Newton patient (PATIENT_FACTOR), and every sub-step's
 * first iterate from the last sub-step's solution (keep_solution), also
 * after one solved afresh, whose first iterate rebuilt from the state
 * started some 5e3 times farther from its solution than its first half's.
 * Every sub-step still converges to the tolerance. Counted
 * (resorted_steps) for the run's warnings: never silent, and no step any
 * earlier try solved gets here, so no run that ran without it changes
 * (docs/decisions/0135-stall-fallback.md). Returns split_step's result. */
static int last_resort(implicit_work *w, const rod_model *m, rod_state *s, double dt,
                       rod_report *report, int split)
{
    if (split != -1 || !w->self) return split;
    restore_state(w, s);
    w->last_resort = 1;
    w->patient = 1;
    w->have_factor = 0;
    /* a caller's own bound (rodsim live's lines) kept as the retries keep it */
    w->budget = (m->options.iteration_budget > 0 ? 1 : RESORT_BUDGET_FACTOR) * step_budget(m);
    split = split_step(w, m, s, dt, report, 0);
    w->patient = 0;
    w->last_resort = 0;
    w->have_factor = 0;
    if (split == 0 && w->resorted_steps++ == 0) w->resorted_first = w->save_time;
    /* a rod of a set: its caller says each step's warning as it comes
     * (a single rod's says the counts at the run's end) */
    if (split == 0 && w->cross && !report->warning[0])
        snprintf(report->warning, sizeof report->warning,
                 "implicit scheme: the step at t = %.6g s, which Newton's method could not "
                 "solve, split down to dt/%d, was solved by the last resort (Newton patient, "
                 "each sub-step from the last one's solution, to the tolerance %.1e)",
                 w->save_time, 1 << MAX_SPLIT_DEPTH, m->options.newton_tolerance);
    return split;
}

/* Nodes over which the non-finite entries of a stalled step's residual
 * may lie for stall_site to name the first one's place */
#define STALL_SITE_SPREAD 4

/* Where a step that did not converge left its residual largest (the last
 * attempt's last evaluation, w->residual): ", its residual stayed largest
 * (...) in the moment balance of node b (s = ... m)". When entries of it
 * are NaN or infinite, no number (it would mean nothing): that it was not
 * finite, how many, and where: the first of them, or, spread beyond
 * STALL_SITE_SPREAD nodes, the nodes they span and the largest of the
 * finite rest. Then what touches the rod there (within two nodes): a
 * surface (its shape and scene line), a puncture or another strand.
 * Returns 1 when something touches it there. */
static int stall_site(const implicit_work *w, const rod_model *m, char *out, size_t len)
{
    out[0] = '\0';
    int worst = -1, first_bad = -1, last_bad = -1, bad_count = 0;
    double big = 0.0;
    for (int i = 0; i < w->unknowns; i++) {
        const double r = w->residual[i];
        if (!isfinite(r)) {
            if (bad_count++ == 0) first_bad = i;
            last_bad = i;
        } else if (fabs(r) > big) {
            big = fabs(r);
            worst = i;
        }
    }
    const int n = w->nodes;
    int used = 0;
    if (first_bad >= 0) {
        const int from = first_bad / w->block + w->first, to = last_bad / w->block + w->first;
        used = snprintf(out, len, "; its residual was not finite (%d of its %d entries NaN or "
                        "infinite", bad_count, w->unknowns);
        if (to - from <= STALL_SITE_SPREAD) {
            worst = first_bad;
            used += snprintf(out + used, len - (size_t)used, "), the first (%s) in",
                             isnan(w->residual[first_bad]) ? "NaN" : "infinite");
        } else {
            used += snprintf(out + used, len - (size_t)used, ", from node %d to node %d of %d)%s",
                             from, to, n, worst >= 0 ? "; of the rest, the largest in" : "");
        }
    }
    if (worst < 0 || used < 0 || (size_t)used >= len) return 0;
    const int node = worst / w->block + w->first, comp = worst % w->block;
    const char *what = w->planar ? "the balances of"
                       : comp < 3    ? "the length constraint (3.14) of the segment up to"
                                     : "the moment balance (3.6)_2 of";
    if (first_bad < 0)
        used = snprintf(out, len, "; its residual stayed largest (%.2g) in", big);
    used += snprintf(out + used, len - (size_t)used, " %s node %d of %d (s = %.4g m)", what, node,
                     n, rod_node_arc(m, node));
    /* a surface within a quarter diameter of a node at the step's start (the
     * last evaluation may have left contact out: a Jacobian's differences) */
    int touching = 0;
    static const int order[5] = {0, -1, 1, -2, 2}; /* the node itself first */
    for (int o = 0; o < 5 && w->contact.surface_count && used > 0 && (size_t)used < len; o++) {
        const int i = node + order[o];
        if (i < 0 || i >= n) continue;
        /* a surface the node is threaded through (beside or between its
         * punctures) does not touch it: left out of its contact */
        int nearest = -1;
        const double *gap = &w->contact.start_gap[7 * (size_t)i * (size_t)w->contact.surface_count];
        for (int j = 0; j < w->contact.surface_count; j++)
            if (!(j < 32 && (w->contact.threaded[i] >> j & 1u)) &&
                (nearest < 0 || gap[7 * j] < gap[7 * nearest]))
                nearest = j;
        if (nearest < 0 || !(gap[7 * nearest] < 0.25 * m->diameter)) continue;
        const rod_surface *sf = &w->contact.surfaces[nearest];
        used += snprintf(out + used, len - (size_t)used, ", where node %d touches the %s of "
                         "line %d", i, rod_surface_name(sf->shape), sf->line);
        touching = 1;
        break;
    }
    for (int k = 0; k < w->contact.puncture_count && used > 0 && (size_t)used < len; k++)
        if (w->contact.punct[k].j >= node - 2 && w->contact.punct[k].j <= node + 1) {
            const int pj = w->contact.punct[k].j;
            const double al = w->contact.punct[k].alpha;
            used += snprintf(out + used, len - (size_t)used, ", beside the puncture at s = %.4g m",
                             m->segment_length ? rod_node_arc(m, pj) + al * m->segment_length[pj]
                                               : (pj + al) * m->ds);
            touching = 1;
            break;
        }
    if (w->self && used > 0 && (size_t)used < len)
        for (int i = node - 2; i <= node + 2; i++)
            if (i >= 0 && i < n && v3_norm(&w->self->node_force[3 * i]) > 0.0) {
                snprintf(out + used, len - (size_t)used, ", pressed by another strand of the rod");
                touching = 1;
                break;
            }
    return touching;
}

static rod_status unresolved(const rod_model *m, const rod_state *s, double angle, int segment,
                             rod_report *report)
{
    rod_unresolved_bend_message(m, "implicit", s->time, angle, segment, report->message,
                                sizeof report->message);
    return ROD_UNSTABLE;
}

/* A step that split and retried without converging: the state restored,
 * and a message saying where it stalled and what may help. */
static rod_status no_convergence(implicit_work *w, const rod_model *m, rod_state *s, double dt,
                                 rod_report *report)
{
    int segment;
    restore_state(w, s);
    w->have_factor = 0;
    double angle = rod_sharpest_bend(m, s->darboux, &segment);
    if (angle > 0.5 * ROD_UNRESOLVED_BEND) return unresolved(m, s, angle, segment, report);
    const int both_held = w->ends[0].held && !w->ends[0].sliding && w->ends[1].held &&
                          !w->ends[1].sliding;
    char site[320];
    const int contact_site = stall_site(w, m, site, sizeof site);
    /* at most 768 bytes (rod_report): a longer one loses its last words */
    const int written = snprintf(report->message, sizeof report->message,
             "implicit scheme: Newton's method did not converge at t = %.6g s for the step "
             "dt = %g s, split in halves down to dt/%d within %d iterations (tolerance %.1e)%s. "
             "%s%s",
             s->time, dt, 1 << w->deepest, step_budget(m), m->options.newton_tolerance,
             site,
             contact_site ? "Contact turning there between touching and not, or stick and slip, "
                            "can stall Newton at any step: a smaller dt may not help; change "
                            "the scene a little there (the shape, the surface, its friction)."
                          : "The load may change too abruptly for this dt, or exceed what the "
                            "rod can carry; try a smaller dt or a ramped load profile.",
             both_held && !contact_site
                 ? " Both ends hold their place: a nearly straight rod between them can "
                   "neither stretch nor shorten without bending, so its tension is "
                   "(nearly) undetermined; start it slightly bent (rod.shape, "
                   "rod.curvature) and let driven ends start from rest." : "");
    if (written >= (int)sizeof report->message) { /* cut at a word, not in one */
        char *end = strrchr(report->message, ' ');
        if (end) *end = '\0';
    }
    report->suggested_dt = dt / (1 << MAX_SPLIT_DEPTH);
    return ROD_NO_CONVERGENCE;
}

/* A step the caller should not ask for: ROD_FAILED with a message, else
 * ROD_OK */
static rod_status refuse(const rod_state *s, double dt, rod_report *report)
{
    if (!(dt > 0.0) || !isfinite(dt)) {
        /* a programming error of the caller; refused rather than split 4096 ways */
        snprintf(report->message, sizeof report->message,
                 "implicit scheme: the step dt = %g s must be a positive finite time", dt);
        return ROD_FAILED;
    }
    if (s->time + dt == s->time) {
        /* below the rounding of t: the step would not advance the time, and a
         * loop stepping until t reaches a target would never end */
        snprintf(report->message, sizeof report->message,
                 "implicit scheme: the step dt = %g s is below the rounding of t = %.17g s and "
                 "would not advance the time; use a larger solver.dt", dt, s->time);
        return ROD_FAILED;
    }
    return ROD_OK;
}

rod_status implicit_step(implicit_work *w, const rod_model *m, rod_state *s, double dt,
                         rod_report *report)
{
    if (refuse(s, dt, report) != ROD_OK) return ROD_FAILED;
    s->staggered = 1;
    save_state(w, s);
    w->budget = step_budget(m);
    w->deepest = 0;
    /* the depth the last steps' motion asked for (SPLIT_HOLD_STEPS) */
    w->start_depth = w->self && implicit_same_dt(w->depth_dt, dt) ? w->next_depth : 0;
    w->motion_depth = -1;
    /* the steps after one that needed patience start patient
     * (PATIENT_HOLD_STEPS) */
    w->patient = w->patient_hold > 0 && w->has_contact;
    w->patience_used = 0;
    if (w->patient_hold > 0) w->patient_hold--;
    int split = split_step(w, m, s, dt, report, 0);
    if (split == 0 && w->patience_used) {
        note_patient(w, m, report);
        w->patient_hold = PATIENT_HOLD_STEPS;
    }
    w->patient = 0;
    if (w->self) hold_split_depth(w, dt, split == 0);
    w->start_depth = 0; /* the retries from the whole step */
    split = retry_with_differences(w, m, s, dt, report, split);
    split = last_resort(w, m, s, dt, report, split);
    report->jacobian_builds = w->jacobian_builds;
    report->newton_total = w->newton_total;
    report->resorted_steps = w->resorted_steps;
    report->resorted_first = w->resorted_first;
    if (split == -2) {
        restore_state(w, s);
        w->have_factor = 0;
        return ROD_FAILED;
    }
    if (split != 0) return no_convergence(w, m, s, dt, report);
    int segment;
    double angle = rod_sharpest_bend(m, s->darboux, &segment);
    if (angle <= ROD_UNRESOLVED_BEND) return ROD_OK;
    return unresolved(m, s, angle, segment, report);
}

int implicit_refresh(implicit_work *w, const rod_model *m, const rod_state *s, double dt)
{
    if (!w->stale || (w->self && w->self->count) || !(dt > 0.0) || !(w->dt_last > 0.0) ||
        !implicit_continues_from(w, s, dt))
        return 0;
    rod_report report;
    memset(&report, 0, sizeof report);
    rod_self_contact *self = w->self; /* no pairs: it takes no part */
    w->self = NULL;
    int continuing;
    int rc = implicit_prepare_step(w, m, s, dt, &report, 0, &continuing);
    const long before = w->jacobian_builds;
    if (rc == 0) rc = implicit_factor_jacobian(w, m, s->time, dt);
    w->builds_by[BUILD_BETWEEN] += w->jacobian_builds - before;
    w->self = self;
    if (self) rod_self_contact_invalidate(self); /* its B^-1 V was for the old band */
    w->start_valid = 1; /* s as the last step left it: the next step continues from it */
    return rc == 0 ? 1 : -1;
}
