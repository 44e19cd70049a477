/* rods_run.c: `rodsim run` of a scene of named rods (rods_run.h). */
#include "cli/rods_run.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "api/scene_keys.h"
#include "api/scene_read.h"
#include "base/clocks.h"
#include "base/outfile.h"
#include "base/vec3.h"
#include "cli/args.h"
#include "cli/knot_across_track.h"
#include "cli/knot_track.h"
#include "cli/run.h"
#include "cli/scene_outputs.h"
#include "cli/summary.h"
#include "sim/contact/between_rods.h"
#include "sim/cut.h"
#include "sim/instrument_overlap.h"
#include "sim/recording.h"
#include "sim/rod_set.h"
#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_coupling.h"

#define RODS_ERR_LEN 1024

/* What the run holds */
typedef struct rods_run {
    const scene_outputs_options *o;
    const char *scene;
    rod_set set;
    run_output out;
    rod_set_run run;
    run_plan plan;
    double dt;
    FILE *csv;
    outfile csv_file;
    int csv_stdout;
    rod_recording *rec[ROD_SET_MAX];
    long long frames;
    double closest_gap;    /* m: between rods, over the run */
    run_warnings warnings; /* the paths' and the steps' (jaws closed on nothing) */
    int warned_steps;      /* the steps' warnings said so far */
    double step_cpu;
    /* each rod's knot per output frame (its own centreline, closed far
     * outside it, as a single rod's), and every change: t s, the type after */
    knot_track knot[ROD_SET_MAX];
    int knot_change_count[ROD_SET_MAX];
    summary_knot_change knot_changes[ROD_SET_MAX][SUMMARY_MAX_KNOT_CHANGES];
    /* the knot each pair of rods makes together (the first pairs in the
     * order), per output frame */
    knot_across_track across[SUMMARY_MAX_KNOTS_ACROSS];
    int across_count;
    /* an elastic pad (the first rod's surface `pad`, shared by all; -1:
     * none): its top nodes per frame, when each rod's punctures were
     * made (s), and the stitches: the rods with punctures, whose gaps the
     * summary follows */
    int pad;
    FILE *tissue_csv;
    outfile tissue_file;
    int punctures_seen[ROD_SET_MAX];
    double puncture_t[ROD_SET_MAX][ROD_MAX_PUNCTURES];
    int stitch_count;
    int stitch_rod[SUMMARY_MAX_STITCHES];
} rods_run;

/* The wound's opening (m) at rod k's stitch: at the mean place of its
 * punctures in the pad (linked, or made in it), or the widest without one */
static double rod_stitch_gap(const rods_run *r, int k)
{
    const rod_state *s = r->run.state[k];
    const tissue_solid *t = r->set.model[0].surfaces[r->pad].solid;
    double at[3] = {0.0, 0.0, 0.0};
    int count = 0;
    for (int p = 0; p < s->puncture_count; p++)
        if (s->puncture[p].linked == r->pad + 1 || s->puncture[p].surface == r->pad) {
            v3_axpy(at, 1.0, s->puncture[p].point);
            count++;
        }
    if (count == 0) return tissue_wound_gap(t);
    v3_scale(at, at, 1.0 / count);
    return tissue_coupling_gap_at(t, at);
}

/* A frame's record of the pad and the punctures: the tissue CSV's rows,
 * the punctures made since the last frame, the gaps for the summary */
static void pad_frame(rods_run *r)
{
    for (int k = 0; k < r->set.count; k++)
        for (; r->punctures_seen[k] < r->run.state[k]->puncture_count &&
               r->punctures_seen[k] < ROD_MAX_PUNCTURES;
             r->punctures_seen[k]++)
            r->puncture_t[k][r->punctures_seen[k]] = r->run.state[k]->time;
    if (r->pad < 0) return;
    const rod_model *m0 = &r->set.model[0];
    const rod_state *s0 = r->run.state[0];
    if (r->tissue_csv) scene_outputs_tissue_csv_frame(r->tissue_csv, m0, s0);
    run_summary *sum = r->o->summary;
    if (!sum) return;
    sum->has_tissue = 1;
    sum->tissue_max_displacement =
        fmax(sum->tissue_max_displacement,
             tissue_coupling_max_displacement(m0->surfaces[r->pad].solid));
    if (sum->gap_count >= SUMMARY_MAX_GAPS) return;
    const int g = sum->gap_count++;
    sum->wound_gap[g][0] = s0->time;
    /* one rod: as the bare [rod]'s; several: the widest, each stitch apart */
    sum->wound_gap[g][1] = r->set.count > 1 ? tissue_wound_gap(m0->surfaces[r->pad].solid)
                                            : scene_outputs_stitch_gap(m0, s0, r->pad);
    for (int q = 0; q < r->stitch_count; q++) sum->stitch_gap[g][q] = rod_stitch_gap(r, r->stitch_rod[q]);
}

/* The model rod k's state is of: after a cut, the thread left's (sim/cut.h) */
static const rod_model *model_now(const rods_run *r, int k)
{
    return rod_cut_model(&r->set.model[k], r->run.state[k]);
}

/* Identifies rod k's knot in this frame and notes a change. The strands'
 * closest approach between frames is not measured in a run of several rods:
 * 0 is passed, so that only strands touching near an end call a change a
 * slip (INFINITY would call every change a loop passing over an end). */
static void track_knot(rods_run *r, int k)
{
    knot_track *t = &r->knot[k];
    const int before = t->changes;
    const rod_state *s = r->run.state[k];
    knot_track_frame(t, model_now(r, k), s, 0.0);
    if (t->changes > before && r->knot_change_count[k] < SUMMARY_MAX_KNOT_CHANGES) {
        summary_knot_change *c = &r->knot_changes[k][r->knot_change_count[k]++];
        c->t = s->time;
        /* both are 96 bytes, the name terminated (a copy: snprintf from one
         * part of r to another reads as an overlap to the compiler) */
        memcpy(c->type, t->last.name, sizeof c->type);
        c->type[sizeof c->type - 1] = '\0';
        const char *how = knot_track_how_text(t->last_how, t->last_end);
        snprintf(c->how, sizeof c->how, "%s", how ? how : "");
    }
}

/* The rod can knot, or was knotted: its knot belongs in the summary */
static int knot_told(const rods_run *r, int k)
{
    return r->knot[k].frames > 0 &&
           (knot_track_can_knot(&r->set.model[k]) || knot_track_was_knotted(&r->knot[k]));
}

/* The pair's knot belongs in the summary: both rods' knots do, or the two
 * were tied together at some frame */
static int across_told(const rods_run *r, const knot_across_track *t)
{
    return t->frames > 0 &&
           ((knot_told(r, t->rod[0]) && knot_told(r, t->rod[1])) || t->changes > 0 ||
            strcmp(t->first.name, "unknot") != 0);
}

/* Trackers for the knots of the first pairs of rods; -1 out of memory */
static int across_init(rods_run *r)
{
    for (int k = 0; k < r->set.count; k++)
        for (int l = k + 1; l < r->set.count && r->across_count < SUMMARY_MAX_KNOTS_ACROSS; l++)
            if (knot_across_track_init(&r->across[r->across_count++], k, l,
                                       r->set.model[k].nodes, r->set.model[l].nodes))
                return -1;
    return 0;
}

/* A frame: the CSV rows of every rod, and the recordings */
static int output_frame(rods_run *r)
{
    const int several = r->set.count > 1;
    for (int k = 0; k < r->set.count; k++) {
        if (r->csv && run_csv_frame_named(r->csv, model_now(r, k), r->run.state[k],
                                          several ? r->set.name[k] : NULL))
            return -1;
        if (r->rec[k] && rod_recording_append(r->rec[k], model_now(r, k), r->run.state[k]))
            return -1;
        track_knot(r, k);
    }
    for (int p = 0; p < r->across_count; p++) {
        knot_across_track *t = &r->across[p];
        const rod_state *a = r->run.state[t->rod[0]], *b = r->run.state[t->rod[1]];
        knot_across_track_frame(t, a->position, a->nodes, b->position, b->nodes, a->time);
    }
    pad_frame(r);
    if (r->tissue_csv && ferror(r->tissue_csv)) return -1;
    r->frames++;
    return 0;
}

/* n steps of h to the output time target */
static rod_status advance(rods_run *r, long long n, double h, double target, rod_report *report)
{
    for (long long j = 0; j < n; j++) {
        /* the user's stop (base/outfile.h) */
        if (outfile_stop_message(r->run.state[0]->time, report->message, sizeof report->message))
            return ROD_FAILED;
        double t0 = cpu_seconds();
        rod_status st = rod_set_step(&r->set, &r->run, h, report);
        r->step_cpu += cpu_seconds() - t0;
        if (st != ROD_OK) return st;
        if (report->warning[0]) { /* said once each (a full list drops the rest) */
            if (r->warned_steps++ < RUN_WARNINGS_MAX / 2)
                run_warn(&r->warnings, "%s", report->warning);
            report->warning[0] = '\0';
        }
        for (int k = 0; k < r->set.count; k++)
            if (!rod_state_is_finite(r->run.state[k])) {
                snprintf(report->message, sizeof report->message,
                         "rod %s: the state is no longer finite at t = %g s", r->set.name[k],
                         r->run.state[k]->time);
                return ROD_UNSTABLE;
            }
        if (r->run.link) r->closest_gap = fmin(r->closest_gap, r->run.link->closest);
    }
    for (int k = 0; k < r->set.count; k++) r->run.state[k]->time = target;
    return ROD_OK;
}

static rod_status simulate_steps(rods_run *r, rod_report *report)
{
    memset(report, 0, sizeof *report);
    if (output_frame(r)) {
        snprintf(report->message, sizeof report->message, "out of memory");
        return ROD_FAILED;
    }
    const double duration = r->set.model[0].options.duration;
    const long long intervals = r->plan.intervals + (r->plan.last_steps > 0 ? 1 : 0);
    for (long long k = 1; k <= intervals; k++) {
        const int partial = k > r->plan.intervals;
        const double target = partial ? duration : fmin((double)k / r->out.fps, duration);
        rod_status st = advance(r, partial ? r->plan.last_steps : r->plan.steps_per_interval,
                                partial ? r->plan.last_step : r->plan.step, target, report);
        if (st != ROD_OK) return st;
        if (output_frame(r)) {
            snprintf(report->message, sizeof report->message, "out of memory");
            return ROD_FAILED;
        }
    }
    return ROD_OK;
}

/* The steps with SIGINT/SIGTERM ending them at a step (noted since the
 * command began); after them one acts at once (base/outfile.h). */
static rod_status simulate(rods_run *r, rod_report *report)
{
    outfile_signal_defer(1);
    rod_status st = simulate_steps(r, report);
    if (outfile_signal_defer(0) && st == ROD_OK &&
        outfile_stop_message(r->run.state[0]->time, report->message, sizeof report->message))
        st = ROD_FAILED;
    return st;
}

/* The result in prose: each rod's tip, held ends and the force of the
 * other rods on it */
static void print_result(const rods_run *r)
{
    if (r->o->quiet) return;
    FILE *f = r->o->talk_stderr || r->csv_stdout ? stderr : stdout;
    fprintf(f, "rodsim run: %s: %d rods, %lld steps of %g s, %lld frames, t = %g s, %.3g s of "
            "CPU in the steps (%.3g ms a step)\n", r->scene, r->set.count, (long long)r->run.steps,
            r->plan.step, r->frames, r->run.state[0]->time, r->step_cpu,
            r->run.steps ? 1e3 * r->step_cpu / (double)r->run.steps : 0.0);
    for (int k = 0; k < r->set.count; k++) {
        const rod_state *s = r->run.state[k];
        const double *tip = &s->position[3 * (s->nodes - 1)];
        const double *c = r->run.touch_force[k];
        fprintf(f, "  rod %s: tip (%.6g, %.6g, %.6g) m; other rods' force on it (%.4g, %.4g, "
                "%.4g) N\n", r->set.name[k], tip[0], tip[1], tip[2], c[0], c[1], c[2]);
        if (knot_told(r, k)) knot_track_print(f, &r->knot[k], &r->set.model[k]);
        /* what the tissue feels at each of its punctures; the scene's first */
        for (int p = 0; p < s->puncture_count; p++) {
            const rod_puncture_state *ps = &s->puncture[p];
            fprintf(f, "        puncture %d at (%.6g, %.6g, %.6g) m (%s): the thread passes at "
                    "s = %.6g m, force on the tissue (%.6g, %.6g, %.6g) N\n", p + 1,
                    ps->point[0], ps->point[1], ps->point[2],
                    p < r->set.model[k].puncture_count ? "given" : "made by the needle", ps->s,
                    ps->force[0] + 0.0, ps->force[1] + 0.0, ps->force[2] + 0.0);
        }
        for (int g = 0; g < s->grasp_log_count; g++) {
            const rod_grasp_record *gr = &s->grasp_log[g];
            char off[64] = "held at the end";
            if (gr->t_off >= 0.0) snprintf(off, sizeof off, "released at t = %.6g s", gr->t_off);
            fprintf(f, "    grasp by %s: at t = %.6g s, %s, rod %s at s = %.6g m, largest "
                    "force on the jaws %.6g N\n", r->set.model[k].instruments[gr->instrument].name,
                    gr->t_on, off, r->set.name[k], gr->s, gr->force);
        }
        for (int q = 0; q < s->cut_count; q++) {
            const rod_cut_record *cr = &s->cut_log[q];
            char who[64] = "the scene's [cut]";
            if (cr->instrument >= 0)
                snprintf(who, sizeof who, "%.40s",
                         r->set.model[k].instruments[cr->instrument].name);
            fprintf(f, "    cut by %s: at t = %.6g s, rod %s at s = %.6g m, %.6g m taken away "
                    "from its %s's side\n", who, cr->t, r->set.name[k], cr->s, cr->removed,
                    cr->side ? "tip" : "root");
        }
    }
    if (r->pad >= 0) {
        const tissue_solid *t = r->set.model[0].surfaces[r->pad].solid;
        fprintf(f, "  elastic pad: its nodes at most %.4g mm from rest; the wound's opening",
                1e3 * tissue_coupling_max_displacement(t));
        for (int q = 0; q < r->stitch_count; q++)
            fprintf(f, "%s at rod %s's stitch %.4g mm", q ? "," : "",
                    r->set.name[r->stitch_rod[q]], 1e3 * rod_stitch_gap(r, r->stitch_rod[q]));
        fprintf(f, "%s widest %.4g mm (below 0: the lips pressed together, by the contact's "
                "give)\n", r->stitch_count ? ";" : "", 1e3 * tissue_wound_gap(t));
        const tissue_costs c = tissue_cost(t);
        fprintf(f, "  the pad's CPU: %.3g s of the steps' %.3g s (%.0f %%); %.4g CPU s per "
                "simulated s in all\n", c.coupling_s, r->step_cpu,
                r->step_cpu > 0.0 ? 100.0 * c.coupling_s / r->step_cpu : 0.0,
                r->run.state[0]->time > 0.0 ? r->step_cpu / r->run.state[0]->time : 0.0);
    }
    for (int p = 0; p < r->across_count; p++)
        if (across_told(r, &r->across[p]))
            knot_across_track_print(f, &r->across[p], r->set.name[r->across[p].rod[0]],
                                    r->set.name[r->across[p].rod[1]]);
    if (isfinite(r->closest_gap))
        fprintf(f, "  closest approach between rods: %.3g m beyond contact\n", r->closest_gap);
    char closest[256]; /* driven instruments: their closest from their paths */
    if (rod_instruments_closest_text(&r->set.model[0], r->run.state[0]->time, closest,
                                     sizeof closest))
        fprintf(f, "  instruments at their closest: %s\n", closest);
    if (r->run.sweeps > 0) /* the steps' sweeps over rods in contact (sim/rod_set.h) */
        fprintf(f, "  contact between rods: %.3g sweeps a step, %ld Newton "
                "solves in all; %ld steps stopped short of the tolerance\n",
                (double)r->run.sweeps / (double)r->run.steps, r->run.solves, r->run.unsettled);
}

/* Rod k's knot at the last frame, and its changes */
static void summary_rod_knot_fill(const rods_run *r, int k, summary_rod_knot *out)
{
    const rod_knot *last = &r->knot[k].last;
    snprintf(out->type, sizeof out->type, "%s", last->name);
    out->terms = last->terms < 32 ? last->terms : 32;
    for (int i = 0; i < out->terms; i++) out->alexander[i] = last->coefficient[i];
    out->determinant = last->determinant;
    out->has_signature = last->has_signature;
    out->signature = last->signature;
    out->rope_d = knot_track_rope(&r->knot[k], &r->set.model[k]); /* NAN: none */
    out->change_count = r->knot_change_count[k];
    memcpy(out->changes, r->knot_changes[k], sizeof out->changes);
}

static void fill_summary(const rods_run *r, run_summary *sum, int ran)
{
    const rod_model *m0 = &r->set.model[0];
    snprintf(sum->scheme, sizeof sum->scheme, "%s", rod_scheme_get(m0->options.scheme)->name);
    sum->has_video_rate = r->out.fps > 0;
    sum->fps = r->out.render.fps;
    sum->speed = r->out.render.speed;
    if (!ran) return;
    sum->has_run = 1;
    sum->steps = r->run.steps;
    sum->frames = r->frames;
    sum->t_end = r->run.state[0]->time;
    scene_outputs_instrument_gap(sum, m0, sum->t_end);
    sum->step_cpu_s = r->step_cpu;
    sum->rod_count = r->set.count < SUMMARY_MAX_RODS ? r->set.count : SUMMARY_MAX_RODS;
    for (int k = 0; k < sum->rod_count; k++) {
        const rod_model *m = model_now(r, k); /* after cuts: the thread left */
        const rod_state *s = r->run.state[k];
        summary_rod *out = &sum->rods[k];
        snprintf(out->name, sizeof out->name, "%s", r->set.name[k]);
        out->nodes = m->nodes;
        v3_copy(out->tip, &s->position[3 * (m->nodes - 1)]);
        const rod_end_kind kinds[2] = {m->root_end, m->tip_end};
        for (int e = 0; e < 2; e++) {
            out->has_end[e] = kinds[e] != ROD_END_FREE;
            v3_copy(out->end_force[e], s->end_force[e]);
            v3_copy(out->end_moment[e], s->end_moment[e]);
        }
        v3_copy(out->contact_force, r->run.touch_force[k]);
        out->min_strand_gap_d = INFINITY;
        out->has_knot = knot_told(r, k);
        if (out->has_knot) summary_rod_knot_fill(r, k, &out->knot);
    }
    sum->puncture_count = 0;
    for (int k = 0; k < r->set.count; k++) {
        const rod_state *s = r->run.state[k];
        for (int p = 0; p < s->puncture_count && sum->puncture_count < SUMMARY_MAX_PUNCTURES; p++) {
            summary_puncture *out = &sum->punctures[sum->puncture_count++];
            out->t = p < r->punctures_seen[k] ? r->puncture_t[k][p] : s->time;
            v3_copy(out->point, s->puncture[p].point);
            v3_copy(out->force, s->puncture[p].force);
            if (r->set.count > 1) snprintf(out->rod, sizeof out->rod, "%s", r->set.name[k]);
        }
    }
    sum->stitch_count = r->stitch_count;
    for (int q = 0; q < r->stitch_count; q++)
        snprintf(sum->stitch_rod[q], sizeof sum->stitch_rod[q], "%s", r->set.name[r->stitch_rod[q]]);
    sum->grasp_count = 0; /* every rod's, in the order of the rods */
    for (int k = 0; k < r->set.count; k++)
        for (int g = 0; g < r->run.state[k]->grasp_log_count && sum->grasp_count < SUMMARY_MAX_GRASPS; g++) {
            const rod_grasp_record *gr = &r->run.state[k]->grasp_log[g];
            summary_grasp *out = &sum->grasps[sum->grasp_count++];
            snprintf(out->instrument, sizeof out->instrument, "%s",
                     r->set.model[k].instruments[gr->instrument].name);
            if (r->set.named) snprintf(out->rod, sizeof out->rod, "%s", r->set.name[k]);
            out->t_on = gr->t_on;
            out->t_off = gr->t_off;
            out->s = gr->s;
            out->force = gr->force;
        }
    sum->cut_count = 0; /* every rod's, in the order of the rods */
    for (int k = 0; k < r->set.count; k++)
        for (int c = 0; c < r->run.state[k]->cut_count && sum->cut_count < SUMMARY_MAX_CUTS; c++) {
            const rod_cut_record *cr = &r->run.state[k]->cut_log[c];
            summary_cut *out = &sum->cuts[sum->cut_count++];
            out->instrument[0] = '\0';
            if (cr->instrument >= 0)
                snprintf(out->instrument, sizeof out->instrument, "%s",
                         r->set.model[k].instruments[cr->instrument].name);
            if (r->set.named) snprintf(out->rod, sizeof out->rod, "%s", r->set.name[k]);
            out->t = cr->t;
            out->s = cr->s;
            out->removed = cr->removed;
        }
    sum->knot_across_count = 0;
    for (int p = 0; p < r->across_count; p++) {
        const knot_across_track *t = &r->across[p];
        if (!across_told(r, t)) continue;
        summary_knot_across *out = &sum->knots_across[sum->knot_across_count++];
        for (int e = 0; e < 2; e++)
            snprintf(out->rods[e], sizeof out->rods[e], "%s", r->set.name[t->rod[e]]);
        knot_across_track_fill(t, &out->knot);
    }
}

/* Opens the CSV and the recordings; an exit status */
static int open_outputs(rods_run *r, char *err, size_t errlen)
{
    const scene_outputs_options *o = r->o;
    r->csv_stdout = o->csv && strcmp(o->csv, "-") == 0;
    if (r->csv_stdout) {
        r->csv = tmpfile(); /* copied to stdout when the run has succeeded */
        if (!r->csv) {
            snprintf(err, errlen, "CSV: cannot make a temporary file");
            return RUN_EXIT_FAILURE;
        }
    } else if (o->csv) {
        if (outfile_open(&r->csv_file, o->csv, err, errlen)) return RUN_EXIT_FAILURE;
        r->csv = r->csv_file.fp;
    }
    if (r->csv) {
        if (r->set.count > 1) run_csv_header_rods(r->csv);
        else run_csv_header(r->csv);
    }
    if (o->tissue_csv) {
        if (r->pad < 0) {
            snprintf(err, errlen, "--tissue-csv %s: the scene has no elastic pad (a [surface] box "
                     "with tissue = yes and model = elastic)", o->tissue_csv);
            return RUN_EXIT_BAD_INPUT;
        }
        if (outfile_open(&r->tissue_file, o->tissue_csv, err, errlen)) return RUN_EXIT_FAILURE;
        r->tissue_csv = r->tissue_file.fp;
        fprintf(r->tissue_csv, "t,node,x,y,z\n");
    }
    for (int k = 0; !o->no_video && k < r->set.count; k++) {
        r->rec[k] = rod_recording_create(&r->set.model[k], r->scene, (int)r->plan.frames);
        if (!r->rec[k]) {
            snprintf(err, errlen, "out of memory for the video's frames");
            return RUN_EXIT_FAILURE;
        }
    }
    return 0;
}

/* The video of every rod; an exit status */
static int write_video(rods_run *r, char *err, size_t errlen)
{
    if (r->o->no_video) return 0;
    rod_recording *joined = r->set.count > 1 ? rod_recording_join(r->rec, r->set.count) : NULL;
    const rod_recording *drawn = r->set.count > 1 ? joined : r->rec[0];
    if (!drawn) {
        snprintf(err, errlen, "video: out of memory");
        return RUN_EXIT_FAILURE;
    }
    int rc = run_write_video(drawn, &r->out, r->o->out_dir, err, errlen);
    rod_recording_destroy(joined);
    return rc ? RUN_EXIT_FAILURE : 0;
}

/* The instruments' paths (the scene's, every rod's alike; scene_outputs.h):
 * warnings, or a refusal in err (-1) */
static int check_paths(rods_run *r, char *err, size_t errlen)
{
    char text[RUN_WARNING_LEN];
    if (scene_outputs_path_checks(&r->set.model[0], r->o->label, &r->warnings, text,
                                  sizeof text) == 0)
        return 0;
    snprintf(err, errlen, "%s; nothing was run", text);
    return -1;
}

int rods_run_scene(const scene_outputs_options *o, ini_doc *doc, const char *scene)
{
    char err[RODS_ERR_LEN] = "";
    rods_run r;
    memset(&r, 0, sizeof r);
    r.o = o;
    r.scene = scene;
    r.closest_gap = INFINITY;
    r.csv_file = (outfile){.fd = -1, .slot = -1};
    r.tissue_file = (outfile){.fd = -1, .slot = -1};
    r.pad = -1;
    int status = RUN_EXIT_BAD_INPUT, ran = 0;
    if (ini_check_keys(doc, scene_keys_rod, err, sizeof err) ||
        scene_read_rods(doc, &r.set, err, sizeof err))
        goto fail;
    if (run_read_output(doc, &r.out, err, sizeof err) || ini_check_unused(doc, err, sizeof err))
        goto fail;
    if (check_paths(&r, err, sizeof err)) goto fail;
    if (!o->silent) run_warnings_print(stderr, "rodsim run", &r.warnings, 0);
    const int path_warnings = r.warnings.count;
    r.dt = rod_set_choose_dt(&r.set, NULL);
    r.pad = tissue_coupling_pad(&r.set.model[0]);
    /* the stitches: the rods that hold punctures or carry a needle */
    for (int k = 0; r.pad >= 0 && r.set.count > 1 && k < r.set.count; k++)
        if ((r.set.model[k].puncture_count > 0 || r.set.model[k].needle_radius > 0.0) &&
            r.stitch_count < SUMMARY_MAX_STITCHES)
            r.stitch_rod[r.stitch_count++] = k;
    if (run_plan_make(&r.set.model[0], r.dt, r.out.fps, &r.plan)) {
        snprintf(err, sizeof err, "%s: solver.duration / solver.dt: too many steps or frames",
                 ini_filename(doc));
        goto fail;
    }
    status = RUN_EXIT_FAILURE;
    if (rod_set_run_create(&r.set, &r.run, err, sizeof err)) goto fail;
    for (int k = 0; k < r.set.count; k++) knot_track_init(&r.knot[k], r.set.model[k].nodes);
    if (across_init(&r)) {
        snprintf(err, sizeof err, "out of memory for the knots across rods");
        goto fail;
    }
    outfile_transaction_begin();
    status = open_outputs(&r, err, sizeof err);
    if (status) goto abort;
    rod_report report;
    rod_status st = simulate(&r, &report);
    ran = 1;
    if (st != ROD_OK) {
        snprintf(err, sizeof err, "%s", report.message);
        status = st == ROD_FAILED ? RUN_EXIT_FAILURE : RUN_EXIT_BAD_INPUT;
        if (o->summary && st != ROD_FAILED) o->summary->status = "unstable";
        goto abort;
    }
    if ((status = write_video(&r, err, sizeof err))) goto abort;
    if (o->csv && !r.csv_stdout && outfile_commit(&r.csv_file, err, sizeof err)) {
        status = RUN_EXIT_FAILURE;
        goto abort;
    }
    if (r.tissue_csv && outfile_commit(&r.tissue_file, err, sizeof err)) {
        status = RUN_EXIT_FAILURE;
        goto abort;
    }
    if (outfile_transaction_commit(err, sizeof err)) {
        status = RUN_EXIT_FAILURE;
        goto abort;
    }
    if (r.csv_stdout) { /* the whole CSV, now that the run succeeded */
        char buffer[1 << 14];
        size_t got;
        rewind(r.csv);
        while ((got = fread(buffer, 1, sizeof buffer, r.csv)) > 0)
            if (fwrite(buffer, 1, got, stdout) != got) break;
        if (fflush(stdout) != 0 || ferror(r.csv)) {
            snprintf(err, sizeof err, "--csv -: standard output could not be written");
            status = RUN_EXIT_FAILURE;
            goto fail;
        }
    }
    status = 0;
    if (!o->silent) run_warnings_print(stderr, "rodsim run", &r.warnings, path_warnings);
    print_result(&r);
    if (o->summary) {
        fill_summary(&r, o->summary, ran);
        for (int w = 0; w < r.warnings.count; w++) summary_add_warning(o->summary, r.warnings.text[w]);
        if (o->csv && !r.csv_stdout) summary_add_file(o->summary, o->csv);
        if (o->tissue_csv) summary_add_file(o->summary, o->tissue_csv);
        if (!o->no_video) {
            char path[SUMMARY_TEXT_LEN];
            for (int k = 0; k < 2; k++) {
                snprintf(path, sizeof path, "%s/%s.%s", o->out_dir, scene, k ? "png" : "mp4");
                summary_add_file(o->summary, path);
            }
        }
    }
    goto done;
abort:
    outfile_abort(&r.csv_file);
    outfile_abort(&r.tissue_file);
    outfile_transaction_abort();
fail:
    if (!o->silent) fprintf(stderr, "rodsim run: %s\n", err);
    if (o->summary) {
        summary_set_message(o->summary, err);
        fill_summary(&r, o->summary, ran && r.run.count > 0);
    }
done:
    if (r.csv_stdout && r.csv) fclose(r.csv);
    for (int k = 0; k < ROD_SET_MAX; k++) {
        rod_recording_destroy(r.rec[k]);
        knot_track_release(&r.knot[k]);
    }
    for (int p = 0; p < r.across_count; p++) knot_across_track_release(&r.across[p]);
    rod_set_run_destroy(&r.run);
    rod_set_release(&r.set);
    return status;
}
