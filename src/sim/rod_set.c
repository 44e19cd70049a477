/* rod_set.c: several rods in one scene (rod_set.h). */
#include "sim/rod_set.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/contact/between_rods.h"
#include "sim/cut.h"
#include "sim/instrument.h"
#include "sim/scene.h"
#include "sim/scheme_implicit.h"
#include "sim/tissue/tissue_coupling.h"

int scene_has_named_rods(const ini_doc *doc, int *count)
{
    const char *names[1];
    *count = ini_section_names(doc, "rod", names, 0);
    return *count > 0;
}

/* What several rods cannot have: the first such part of model k, as a
 * message at its line, or 0 */
static int refuse_for_several(ini_doc *doc, const rod_set *set, int k, char *err, size_t errlen)
{
    const rod_model *m = &set->model[k];
    const char *rod = set->name[k];
    if (m->options.scheme != ROD_SCHEME_IMPLICIT)
        return ini_error(doc, "solver", 0, "scheme", err, errlen,
                         "several rods ([rod %s] and others) are stepped by the implicit scheme "
                         "only; accepted here: implicit", rod);
    return 0;
}

/* Reads rod k of a named set: [rod NAME], [ends NAME], [tip NAME] read as
 * [rod], [ends], [tip] (ini_alias), so every key and message is the single
 * rod's */
static int read_named(ini_doc *doc, rod_set *set, int k, char *err, size_t errlen)
{
    char rod[ROD_NAME_LEN + 8], ends[ROD_NAME_LEN + 8], tip[ROD_NAME_LEN + 8];
    snprintf(rod, sizeof rod, "rod %s", set->name[k]);
    snprintf(ends, sizeof ends, "ends %s", set->name[k]);
    snprintf(tip, sizeof tip, "tip %s", set->name[k]);
    int rc = ini_alias(doc, "rod", rod) || ini_alias(doc, "ends", ends) ||
             ini_alias(doc, "tip", tip);
    if (rc) snprintf(err, errlen, "%s: [rod %s]: the name is too long", ini_filename(doc), set->name[k]);
    else rc = scene_read_rod_of(doc, &set->model[k], set->name[k], k > 0 ? &set->model[0] : NULL,
                                err, errlen);
    ini_alias(doc, "rod", NULL);
    ini_alias(doc, "ends", NULL);
    ini_alias(doc, "tip", NULL);
    return rc ? -1 : 0;
}

/* [ends NAME] or [tip NAME] naming no rod: the first, as a message */
static int refuse_orphans(const ini_doc *doc, const rod_set *set, char *err, size_t errlen)
{
    static const char *const words[] = {"ends", "tip"};
    for (int w = 0; w < 2; w++) {
        const char *names[64];
        int n = ini_section_names(doc, words[w], names, 64);
        for (int i = 0; i < n && i < 64; i++) {
            int found = 0;
            for (int k = 0; k < set->count; k++) found |= strcmp(names[i], set->name[k]) == 0;
            if (found) continue;
            char section[ROD_NAME_LEN + 80];
            snprintf(section, sizeof section, "%s %s", words[w], names[i]);
            snprintf(err, errlen, "%s:%d: [%s] names no rod; accepted: the NAME of a [rod NAME]",
                     ini_filename(doc), ini_section_line(doc, section, 0), section);
            return -1;
        }
    }
    return 0;
}

/* Every [puncture]'s rod key names a rod of the set (`names`, `count` of
 * them); with several rods it is required. 0, or -1 with a message. */
static int check_section_rods(ini_doc *doc, const char *section, const char *what,
                              const char *const *names, int count, char *err, size_t errlen)
{
    char listed[ROD_SET_MAX * (ROD_NAME_LEN + 2)] = "";
    for (int k = 0; k < count && k < ROD_SET_MAX; k++) {
        size_t used = strlen(listed);
        snprintf(listed + used, sizeof listed - used, "%s%.*s", k ? ", " : "", ROD_NAME_LEN - 1,
                 names[k]);
    }
    const int sections = ini_section_count(doc, section);
    for (int i = 0; i < sections; i++) {
        const char *rod = NULL;
        if (ini_get_string(doc, section, i, "rod", &rod, err, errlen) < 0) return -1;
        if (!rod && count > 1)
            return ini_error(doc, section, i, "rod", err, errlen,
                             "missing; required with several rods: the NAME of the [rod NAME] "
                             "%s; accepted: %s", what, listed);
        int found = !rod;
        for (int k = 0; k < count && !found; k++) found = strcmp(rod, names[k]) == 0;
        if (!found)
            return ini_error(doc, section, i, "rod", err, errlen,
                             "names no rod of the scene; accepted: %s", listed);
    }
    return 0;
}

int scene_read_rods(ini_doc *doc, rod_set *set, char *err, size_t errlen)
{
    memset(set, 0, sizeof *set);
    const char *names[ROD_SET_MAX + 1];
    const int named = ini_section_names(doc, "rod", names, ROD_SET_MAX + 1);
    if (named == 0) {
        set->count = 1;
        snprintf(set->name[0], ROD_NAME_LEN, "rod");
        return scene_read_rod(doc, &set->model[0], err, errlen);
    }
    set->named = 1;
    static const char *const bare[] = {"rod", "ends", "tip"};
    for (int w = 0; w < 3; w++)
        if (ini_section_line(doc, bare[w], 0) > 0 || ini_section_count(doc, bare[w]) > 0) {
            snprintf(err, errlen, "%s:%d: [%s] in a scene of named rods ([rod %s]); accepted: "
                     "[%s NAME] for each rod (a bare [rod] is a scene's single rod)",
                     ini_filename(doc), ini_section_line(doc, bare[w], 0), bare[w], names[0],
                     bare[w]);
            return -1;
        }
    if (named > ROD_SET_MAX) {
        snprintf(err, errlen, "%s:%d: [rod %s]: more than %d rods; accepted: at most %d",
                 ini_filename(doc), 0, names[ROD_SET_MAX], ROD_SET_MAX, ROD_SET_MAX);
        return -1;
    }
    if (check_section_rods(doc, "puncture", "the thread passing through it is", names, named,
                           err, errlen) ||
        check_section_rods(doc, "point_load", "it loads", names, named, err, errlen) ||
        check_section_rods(doc, "cut", "it cuts", names, named, err, errlen))
        return -1;
    for (int k = 0; k < named; k++) {
        if (strlen(names[k]) >= ROD_NAME_LEN) {
            char section[ROD_NAME_LEN * 4];
            snprintf(section, sizeof section, "rod %.*s", ROD_NAME_LEN * 3, names[k]);
            snprintf(err, errlen, "%s:%d: [%s]: the name is longer than %d characters",
                     ini_filename(doc), ini_section_line(doc, section, 0), section,
                     ROD_NAME_LEN - 1);
            rod_set_release(set);
            return -1;
        }
        snprintf(set->name[k], ROD_NAME_LEN, "%s", names[k]);
        if (read_named(doc, set, k, err, errlen)) {
            rod_set_release(set);
            return -1;
        }
        set->count = k + 1;
        if (named > 1 && refuse_for_several(doc, set, k, err, errlen)) {
            rod_set_release(set);
            return -1;
        }
    }
    if (refuse_orphans(doc, set, err, errlen)) {
        rod_set_release(set);
        return -1;
    }
    const int pad = tissue_coupling_pad(&set->model[0]) >= 0;
    for (int k = 0; k < set->count; k++) /* rod = NAME: the other rods' grasps off */
        for (int i = 0; i < set->model[k].instrument_count; i++) {
            rod_instrument *in = &set->model[k].instruments[i];
            in->grasp_off = in->rod[0] && strcmp(in->rod, set->name[k]) != 0;
        }
    for (int k = 0; named > 1 && k < set->count; k++) {
        set->model[k].between_rods = 1;
        set->model[k].physics.planar = 0; /* the others may push it out of any plane */
        set->model[k].pad_by_set = pad;   /* one pad, coupled once a step for all */
    }
    return 0;
}

void rod_set_release(rod_set *set)
{
    for (int k = 0; k < set->count; k++) rod_model_release(&set->model[k]);
    set->count = 0;
}

int rod_set_run_create(const rod_set *set, rod_set_run *run, char *err, size_t errlen)
{
    memset(run, 0, sizeof *run);
    for (int k = 0; k < set->count; k++) {
        run->state[k] = rod_state_create(&set->model[k]);
        if (!run->state[k]) {
            snprintf(err, errlen, "out of memory");
            rod_set_run_destroy(run);
            return -1;
        }
        run->count = k + 1;
        rod_state_reset(&set->model[k], run->state[k]);
        char why[512];
        if (rod_solver_init(&run->solver[k], &set->model[k], why, sizeof why)) {
            snprintf(err, errlen, "rod %s: %s", set->name[k], why);
            rod_set_run_destroy(run);
            return -1;
        }
    }
    if (set->count > 1) {
        const char *names[ROD_SET_MAX];
        const rod_model *models[ROD_SET_MAX];
        for (int k = 0; k < set->count; k++) names[k] = set->name[k], models[k] = &set->model[k];
        run->link = rod_link_create(set->count, models, names);
        for (int k = 0; run->link && k < set->count; k++) {
            run->begin[k] = rod_state_create(&set->model[k]);
            if (!run->begin[k]) {
                rod_link_destroy(run->link);
                run->link = NULL;
            }
        }
        if (!run->link) {
            snprintf(err, errlen, "out of memory");
            rod_set_run_destroy(run);
            return -1;
        }
        for (int k = 0; k < set->count; k++)
            rod_implicit_link(run->solver[k].work, &run->link->cross[k]);
    }
    return 0;
}

void rod_set_run_destroy(rod_set_run *run)
{
    for (int k = 0; k < run->count; k++) {
        rod_solver_release(&run->solver[k]);
        rod_state_destroy(run->state[k]);
        if (run->begin[k]) rod_state_destroy(run->begin[k]);
    }
    rod_link_destroy(run->link);
    memset(run, 0, sizeof *run);
}

/* The models the rods' states are of: a cut rod's is the thread left's
 * (rod_cut_model) */
static void current_models(const rod_set *set, const rod_set_run *run, const rod_model **out)
{
    for (int k = 0; k < set->count; k++) out[k] = rod_cut_model(&set->model[k], run->state[k]);
}

/* Rod k's solver made again for the thread its state holds (after a cut,
 * or back to the whole thread after a restore), linked to the other rods
 * again. 0, or -1 with the message naming the rod. */
static int sync_rod(const rod_set *set, rod_set_run *run, int k, rod_report *report)
{
    char why[sizeof report->message];
    if (rod_cut_solver_sync(&run->solver[k], &set->model[k], run->state[k], why, sizeof why)) {
        snprintf(report->message, sizeof report->message, "rod %s: %.700s", set->name[k], why);
        return -1;
    }
    if (run->link) {
        rod_implicit_link(run->solver[k].work, &run->link->cross[k]);
        rod_link_cut(run->link, k, run->state[k]->nodes);
    }
    return 0;
}

/* Rod k's solve of the step (from run->begin[k] when `again`) */
static rod_status solve_one(const rod_set *set, rod_set_run *run, int k, double dt, int again,
                            rod_report *report)
{
    const rod_state *const *states = (const rod_state *const *)run->state;
    if (again) rod_state_copy(run->state[k], run->begin[k]);
    if (run->link) rod_link_before(run->link, k);
    rod_status st = rod_solver_step(&run->solver[k], &set->model[k], run->state[k], dt, report);
    run->solves++;
    if (st != ROD_OK) {
        char why[sizeof report->message];
        snprintf(why, sizeof why, "%s", report->message);
        if (set->count > 1)
            snprintf(report->message, sizeof report->message, "rod %s: %.700s", set->name[k], why);
        return st;
    }
    if (run->link) {
        const rod_model *models[ROD_SET_MAX];
        current_models(set, run, models);
        rod_link_after(run->link, k, models, states, dt);
    }
    return ROD_OK;
}

/* The pad the rods share, once a step after every rod's solve: every
 * rod's punctures and contact load it, and its motion moves every rod's
 * punctures (tissue_coupling_step_rods). 0, or -1 with the message. */
static int couple_pad(const rod_set *set, rod_set_run *run, rod_report *report)
{
    const rod_model *models[ROD_SET_MAX];
    double *records[ROD_SET_MAX];
    current_models(set, run, models);
    for (int k = 0; k < set->count; k++) records[k] = rod_implicit_pad_record(run->solver[k].work);
    return tissue_coupling_step_rods(set->count, models, run->state, records, report->message,
                                     sizeof report->message);
}

/* Scissors i closed: the cut asked of the rod nearest their blades' middle
 * line within their reach (of the rods they may cut: [instrument] rod);
 * none near: the warning a single rod gives */
static void scissors_close(const rod_set *set, rod_set_run *run, const rod_model **models,
                           int i, rod_report *report)
{
    int best = -1;
    double best_gap = INFINITY, best_arc = 0.0, nearest = INFINITY, nearest_reach = 0.0;
    for (int k = 0; k < set->count; k++) {
        if (set->model[k].instruments[i].grasp_off) continue;
        double arc, reach;
        const double gap = rod_cut_nearest(models[k], i, run->state[k], &arc, &reach);
        if (gap < nearest) nearest = gap, nearest_reach = reach;
        if (gap <= reach && gap < best_gap) best = k, best_gap = gap, best_arc = arc;
    }
    if (best >= 0) rod_cut_ask(run->state[best], i, best_arc);
    else rod_cut_missed(&set->model[0].instruments[i], run->state[0]->time, nearest,
                        nearest_reach, report);
}

/* After the step: jaws that closed take the rod nearest their middle line
 * within their reach (of the rods they may take: [instrument] rod), once;
 * none near: the warning a single rod gives. Scissors that closed ask the
 * nearest rod for a cut; a holder holding the needle takes nothing. */
static void take_grasps(const rod_set *set, rod_set_run *run, rod_report *report)
{
    const rod_model *m0 = &set->model[0];
    const rod_model *models[ROD_SET_MAX];
    current_models(set, run, models);
    for (int i = 0; i < m0->instrument_count && i < ROD_MAX_INSTRUMENTS; i++) {
        const rod_instrument *in = &m0->instruments[i];
        double jaw;
        rod_pose pose;
        rod_instrument_pose(in, run->state[0]->time, &pose, &jaw);
        const int closed = jaw < ROD_JAW_CLOSED, closing = closed && !run->jaw_closed[i];
        run->jaw_closed[i] = closed;
        int needle = 0; /* the needle is on one rod's tip: its model's copy says so */
        for (int k = 0; k < set->count; k++) needle |= set->model[k].instruments[i].needle;
        if (!closing || needle) continue;
        if (in->kind == ROD_INSTRUMENT_SCISSORS) {
            scissors_close(set, run, models, i, report);
            continue;
        }
        int best = -1;
        double best_gap = INFINITY, best_arc = 0.0, nearest = INFINITY, nearest_reach = 0.0;
        for (int k = 0; k < set->count; k++) {
            if (set->model[k].instruments[i].grasp_off) continue;
            double arc, reach;
            const double gap = rod_grasp_nearest(models[k], i, run->state[k], &arc, &reach);
            if (gap < nearest) nearest = gap, nearest_reach = reach;
            if (gap <= reach && gap < best_gap) best = k, best_gap = gap, best_arc = arc;
        }
        if (best >= 0) rod_grasp_take(models[best], i, run->state[best], best_arc);
        else rod_grasp_missed(in, run->state[0]->time, nearest, nearest_reach, report);
    }
}

/* The cuts due after the step that began at t0: the scene's [cut]s of each
 * rod, and what scissors asked for; each rod cut gets its solver made for
 * the thread left and its link to the others again (sim/cut.h) */
static rod_status make_cuts(const rod_set *set, rod_set_run *run, double t0, rod_report *report)
{
    for (int k = 0; k < set->count; k++) {
        const rod_model *m = &set->model[k];
        rod_state *s = run->state[k];
        if (m->cut_event_count > 0) rod_cut_scene_events(m, s, t0);
        if (!s->cut_request.pending) continue;
        const int before = s->cut_count, warned = report->warning[0] != '\0';
        if (rod_cut_apply(m, s, report)) {
            char why[sizeof report->message];
            snprintf(why, sizeof why, "%s", report->message);
            snprintf(report->message, sizeof report->message, "rod %s: %.700s", set->name[k], why);
            return ROD_FAILED;
        }
        if (!warned && report->warning[0]) { /* the cut dropped: which rod's */
            char why[sizeof report->warning];
            snprintf(why, sizeof why, "%s", report->warning);
            snprintf(report->warning, sizeof report->warning, "rod %.31s: %.440s", set->name[k],
                     why);
        }
        if (s->cut_count != before && sync_rod(set, run, k, report)) return ROD_FAILED;
    }
    return ROD_OK;
}

rod_status rod_set_step(const rod_set *set, rod_set_run *run, double dt, rod_report *report)
{
    rod_link *l = run->link;
    if (!l) {
        rod_status st = solve_one(set, run, 0, dt, 0, report);
        if (st == ROD_OK) run->steps++;
        return st;
    }
    /* a state restored to another thread than its solver's (rodsim_restore) */
    for (int k = 0; k < set->count; k++)
        if (run->solver[k].cuts != run->state[k]->cut_count && sync_rod(set, run, k, report))
            return ROD_FAILED;
    const double t0 = run->state[0]->time;
    const rod_state *const *states = (const rod_state *const *)run->state;
    const rod_model *models[ROD_SET_MAX];
    current_models(set, run, models);
    const int full = rod_link_begin(l, models, states, dt);
    if (full >= 0) {
        snprintf(report->message, sizeof report->message,
                 "rod %s: at t = %.6g s it lies along the other rods at more points than "
                 "its pairs' room (%d); use fewer nodes", set->name[full],
                 run->state[full]->time, l->cross[full].capacity);
        return ROD_FAILED;
    }
    double tolerance = 0.0;
    int any = 0;
    for (int k = 0; k < set->count; k++) {
        tolerance = fmax(tolerance, set->model[k].options.newton_tolerance);
        if (l->involved[k]) rod_state_copy(run->begin[k], run->state[k]), any = 1;
    }
    /* sweeps in the owners-first order: an owner solves against the other
     * rods' last motion, the other rods with its last forces; a rod in no
     * pair solves once. The sweeps end when the last solves of the rods
     * held by others change no pair's force by more than the tolerance:
     * every pair's force then acts on both its rods, equal and opposite */
    double scale = 0.0;
    int sweep = 0;
    for (;; sweep++) {
        l->mismatch = 0.0;
        l->largest = 0.0;
        for (int x = 0; x < set->count; x++) {
            const int k = l->order[x];
            if (sweep > 0 && !l->involved[k]) continue;
            rod_status st = solve_one(set, run, k, dt, sweep > 0, report);
            if (st != ROD_OK) return st;
        }
        if (!any) break;
        run->sweeps++;
        scale = fmax(scale, l->largest);
        if (l->mismatch <= ROD_SET_SWEEP_TOLERANCE * tolerance * scale) break;
        if (sweep + 1 == ROD_SET_SWEEPS) {
            run->unsettled++;
            break;
        }
        rod_link_relax(l, sweep);
    }
    for (int k = 0; k < set->count; k++) rod_cross_total(&l->cross[k], run->touch_force[k]);
    if (set->model[0].pad_by_set && couple_pad(set, run, report)) return ROD_FAILED;
    take_grasps(set, run, report);
    if (make_cuts(set, run, t0, report) != ROD_OK) return ROD_FAILED;
    run->steps++;
    return ROD_OK;
}

double rod_set_choose_dt(const rod_set *set, const char **why)
{
    double dt = INFINITY;
    for (int k = 0; k < set->count; k++) {
        const char *w = NULL;
        double d = rod_choose_dt(&set->model[k], &w);
        if (d < dt) {
            dt = d;
            if (why) *why = w;
        }
    }
    return dt;
}
