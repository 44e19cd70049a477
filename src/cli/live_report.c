/* live_report.c: the summary of a `rodsim live` session of one rod at its
 * end (live_session.h): the lines' outcomes, the Newton work, the
 * distributions of the work and CPU per line, and an elastic pad's costs. */
#include "base/numfmt.h"
#include "cli/live_session.h"
#include "cli/scene_outputs.h"
#include "sim/tissue/tissue_coupling.h"

/* Bins of 1 us of the per-line timing histograms: 20 ms, the last bin
 * holding anything longer. */
#define LIVE_HISTOGRAM_BINS 20000

void live_histogram_add(unsigned *bins, double seconds)
{
    double us = seconds * 1e6;
    int bin = us < 0.0 ? 0 : us >= LIVE_HISTOGRAM_BINS - 1 ? LIVE_HISTOGRAM_BINS - 1 : (int)us;
    bins[bin]++;
}

/* The q-quantile (0..1) of `count` values in the histogram, us: the upper
 * edge of the bin that holds it (the last bin: a lower bound). Over the
 * values the bins hold when fewer (a line --on-error stop ended is counted
 * but not timed): an empty histogram's is 0, not the last bin's 20 ms. */
static double histogram_quantile(const unsigned *bins, long count, double q)
{
    long held = 0;
    for (int i = 0; i < LIVE_HISTOGRAM_BINS; i++) held += bins[i];
    if (count > held) count = held;
    if (count <= 0) return 0.0;
    long rank = (long)(q * (double)(count - 1)), seen = 0;
    for (int i = 0; i < LIVE_HISTOGRAM_BINS; i++) {
        seen += bins[i];
        if (seen > rank) return i + 1.0;
    }
    return LIVE_HISTOGRAM_BINS;
}

/* An elastic pad's line: the wound's gap at the stitch and the punctures'
 * forces at the end (as `rodsim run`'s summary gives them), and what its
 * part of a line's CPU is made of (tissue_costs since the session began) */
static void print_pad(live_session *ls)
{
    const rod_state *s = ls->state;
    const int pad = tissue_coupling_pad(ls->model);
    fprintf(ls->msg, "rodsim live: the pad at t = %.9g s: wound gap %.9g m; punctures' forces "
                     "(N):", s->time, scene_outputs_stitch_gap(ls->model, s, pad));
    for (int k = 0; k < s->puncture_count; k++)
        if (s->puncture[k].linked == pad + 1)
            fprintf(ls->msg, " %.9g %.9g %.9g;", s->puncture[k].force[0],
                    s->puncture[k].force[1], s->puncture[k].force[2]);
    const tissue_costs c = tissue_cost(ls->pad), b = ls->pad_start;
    const double per = ls->lines ? 1e6 / (double)ls->lines : 0.0;
    const double coupling = c.coupling_s - b.coupling_s;
    fprintf(ls->msg, " CPU a line: the pad's coupling %.1f us (assembly %.1f, inversion tests %.1f, "
                     "%ld factorisations %.1f, %ld solves %.1f), the rest (the rod) %.1f us; "
                     "%ld factors renewed behind (%.1f ms CPU on their thread)\n",
            per * coupling, per * (c.assembly_s - b.assembly_s), per * (c.check_s - b.check_s),
            tissue_factorisations(ls->pad) - ls->pad_factorisations - (c.behind_taken - b.behind_taken),
            per * (c.factor_s - b.factor_s), c.solves - b.solves, per * (c.solve_s - b.solve_s),
            per * ls->cpu_sum - per * coupling, c.behind_taken - b.behind_taken,
            1e3 * (c.behind_s - b.behind_s));
}

void live_print_summary(live_session *ls)
{
    /* the work per line, then what it is made of: what the latency adds
     * beyond it is the pipes and the scheduler */
    const long stepped = ls->answered_ok + ls->failed;
    const double per_line = ls->lines ? 1e6 / (double)ls->lines : 0.0;
    fprintf(ls->msg, "rodsim live: %ld lines: %ld ok, %ld failed (%ld moved part of the way "
                     "or held), %ld bad; %ld steps to t = %g s (%ld Jacobian builds: %ld within "
                     "steps, %ld between lines, mean %.0f us); Newton iterations a line: ok "
                     "mean %.1f, max %ld; failed mean %.1f, max %ld (%ld Jacobian builds; "
                     "budget %d to %d "
                     "a try of a step); work per line mean %.1f us, p50 %.0f, p99 %.0f, p99.9 "
                     "%.0f, max %.1f us; mean parse %.1f us, step %.1f us (p99 %.0f us), "
                     "answer %.1f us",
            ls->lines, ls->answered_ok, ls->failed, ls->partial, ls->bad, ls->steps,
            ls->state->time, ls->jacobian_builds, ls->jacobian_builds - ls->idle_builds,
            ls->idle_builds, ls->idle_builds ? 1e6 * ls->idle_sum / (double)ls->idle_builds : 0.0,
            ls->answered_ok ? (double)ls->ok_iterations / (double)ls->answered_ok : 0.0,
            ls->ok_iterations_max,
            ls->failed ? (double)ls->failed_iterations / (double)ls->failed : 0.0,
            ls->failed_iterations_max, ls->failed_builds_max,
            LIVE_STEP_BUDGET_MIN, ls->budget_max, per_line * ls->step_wall_sum,
            histogram_quantile(ls->work_histogram, ls->lines, 0.5),
            histogram_quantile(ls->work_histogram, ls->lines, 0.99),
            histogram_quantile(ls->work_histogram, ls->lines, 0.999), 1e6 * ls->step_wall_max,
            per_line * ls->parse_sum, stepped ? 1e6 * ls->step_sum / (double)stepped : 0.0,
            histogram_quantile(ls->step_histogram, stepped, 0.99),
            stepped ? 1e6 * ls->answer_sum / (double)stepped : 0.0);
    fprintf(ls->msg, "; CPU per line mean %.1f us, p50 %.0f, p99 %.0f, max %.1f us (line %ld)",
            per_line * ls->cpu_sum, histogram_quantile(ls->cpu_histogram, ls->lines, 0.5),
            histogram_quantile(ls->cpu_histogram, ls->lines, 0.99), 1e6 * ls->cpu_max,
            ls->cpu_max_line);
    if (ls->set.realtime)
        fprintf(ls->msg, "; realtime overruns %ld (worst %.1f us)", ls->overruns,
                1e6 * ls->worst_overrun);
    fprintf(ls->msg, "%s\n", live_stop_signal ? "; ended by a signal" : "");
    if (ls->pad) print_pad(ls);
}
