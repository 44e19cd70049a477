/* live_session.c: a `rodsim live` session of one rod made, started,
 * finished and destroyed (live.h's live_session_*; its parts:
 * live_session.h): everything the lines need made here. */
#define _GNU_SOURCE /* sched_getscheduler */
#include <sched.h>
#include <stdlib.h>
#include <string.h>

#include "base/clocks.h"
#include "base/numfmt.h"
#include "cli/args.h"
#include "cli/live_session.h"
#include "sim/tissue/tissue_coupling.h"

/* Sets the session up from the scene's model; 0 or -1 with a message. */
static int setup(live_session *ls, rod_model *m, char *err, size_t errlen)
{
    ls->model = m;
    ls->dt = rod_choose_dt(m, NULL);
    ls->pose_mode = m->tip_end != ROD_END_FREE;
    ls->driven = ls->pose_mode ? 1 : 0;
    ls->columns = ls->pose_mode ? (m->tip_end == ROD_END_CLAMPED ? 7 : 4) : 7;
    ls->state = rod_state_create(m);
    ls->good = rod_state_create(m);
    ls->work_histogram = calloc(LIVE_HISTOGRAM_BINS, sizeof *ls->work_histogram);
    ls->step_histogram = calloc(LIVE_HISTOGRAM_BINS, sizeof *ls->step_histogram);
    ls->cpu_histogram = calloc(LIVE_HISTOGRAM_BINS, sizeof *ls->cpu_histogram);
    ls->answer = malloc((size_t)(8 + 3 * m->nodes) * (NUMFMT_MAX + 1) + 16);
    const int pad = tissue_coupling_pad(m);
    ls->pad = pad >= 0 ? m->surfaces[pad].solid : NULL;
    if (ls->pad) ls->pad_good = malloc(sizeof(double) * tissue_state_doubles(ls->pad));
    if (!ls->state || !ls->good || !ls->work_histogram || !ls->step_histogram || !ls->cpu_histogram ||
        !ls->answer ||
        (ls->pad && !ls->pad_good)) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    /* a line's work bounded: a pose beyond reach fails within this, then
     * is tried part of the way (live_line_tries) */
    m->options.iteration_budget = LIVE_STEP_BUDGET_MIN;
    rod_state_reset(m, ls->state);
    if (ls->pose_mode) {
        if (m->tip_motion) {
            fprintf(ls->msg, "rodsim live: the live input replaces the scene's ends.tip_motion\n");
            rod_path_destroy(m->tip_motion);
            m->tip_motion = NULL;
        }
        memcpy(&ls->last_row[1], &ls->state->position[3 * (m->nodes - 1)], 3 * sizeof(double));
        if (!(ls->path = rod_path_create_live(ls->columns, ls->last_row, err, errlen))) return -1;
        m->tip_motion = ls->path;
        ls->stepped = m;
    } else {
        ls->loads_model = *m; /* shares what m owns; only m is released */
        double f[3], mo[3];
        rod_tip_load(m, 0.0, f, mo);
        memcpy(&ls->last_row[1], f, sizeof f);
        memcpy(&ls->last_row[4], mo, sizeof mo);
        memcpy(ls->table, ls->last_row, sizeof ls->last_row);
        ls->loads_model.profile.kind = ROD_PROFILE_TABLE;
        ls->loads_model.profile.table.columns = 7;
        ls->loads_model.profile.table.rows = 1;
        ls->loads_model.profile.table.data = ls->table;
        ls->stepped = &ls->loads_model;
    }
    if (live_instruments_start(ls, m, err, errlen)) return -1;
    live_needle_init(&ls->needle, m);
    if (rod_solver_init(&ls->solver, ls->stepped, err, errlen)) return -1;
    if (ls->pad) {
        /* the punctures linked and their compliances made now, not in the
         * first line's step (the same work on the same state: the same
         * answers), so the first answer waits for none of it */
        if (tissue_coupling_link(ls->stepped, ls->state, err, errlen)) return -1;
        /* a factorisation is a line's stall (10-15 ms on the wound pad
         * against about 1 ms a line): it is made on a thread of its own
         * while the kept factor serves, and at once only when the kept
         * one stops converging (docs/decisions/0104-live-pad.md) */
        tissue_keep_factor(ls->pad, LIVE_PAD_KEEP_FALL);
        if (tissue_factor_behind(ls->pad, LIVE_PAD_BEHIND_SOLVES, err, errlen)) return -1;
        ls->pad_start = tissue_cost(ls->pad);
        ls->pad_factorisations = tissue_factorisations(ls->pad);
    }
    return 0;
}

live_session *live_session_create(rod_model *m, const live_settings *settings, char *err,
                                  size_t errlen)
{
    live_session *ls = calloc(1, sizeof *ls);
    if (!ls) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    ls->set = *settings;
    ls->out = settings->answers ? settings->answers : stdout;
    ls->msg = settings->messages ? settings->messages : stderr;
    ls->max_ahead = settings->max_steps_ahead > 0 ? settings->max_steps_ahead
                                                  : LIVE_MAX_STEPS_AHEAD;
    if (setup(ls, m, err, errlen)) {
        live_session_destroy(ls);
        return NULL;
    }
    const int policy = sched_getscheduler(0);
    ls->realtime_policy = policy == SCHED_FIFO || policy == SCHED_RR;
    return ls;
}

void live_session_start(live_session *ls)
{
    /* t = 0 on the wall clock before the header goes out: a client that
     * paces itself from the header on is then never ahead of rodsim's clock
     * (taken after, the header's reader could start its clock first, and
     * --realtime would hold every line back by the difference) */
    ls->wall_origin = wall_seconds();
    fprintf(ls->out, "t,fx,fy,fz,mx,my,mz,status");
    if (ls->set.centreline)
        for (int i = 0; i < ls->state->nodes; i++) fprintf(ls->out, ",x%d,y%d,z%d", i, i, i);
    fputc('\n', ls->out);
    fflush(ls->out);
}

int live_session_finish(live_session *ls, int end_of_input)
{
    if (ls->finished) return ls->status;
    ls->finished = 1;
    if (end_of_input && !ls->ended && (ls->line_len > 0 || ls->nul_at)) live_line_done(ls);
    live_close_run(ls);
    live_print_summary(ls);
    if (ls->status == RUN_EXIT_OK && ls->lines > 0 && ls->answered_ok == 0) {
        fprintf(ls->msg, "rodsim live: none of the %ld lines was answered ok (exit 2)\n",
                ls->lines);
        ls->status = RUN_EXIT_BAD_INPUT;
    }
    return ls->status;
}

void live_session_destroy(live_session *ls)
{
    if (!ls) return;
    if (ls->record) fclose(ls->record); /* what was recorded stays */
    if (ls->solver.ops) rod_solver_release(&ls->solver);
    rod_state_destroy(ls->state);
    rod_state_destroy(ls->good);
    free(ls->pad_good);
    free(ls->work_histogram);
    free(ls->step_histogram);
    free(ls->cpu_histogram);
    free(ls->answer);
    free(ls);
}
