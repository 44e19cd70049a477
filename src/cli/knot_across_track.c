/* knot_across_track.c: see knot_across_track.h. */
#include "cli/knot_across_track.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/clocks.h"
#include "cli/knot_track.h"
#include "sim/geometry/knot_across.h"

int knot_across_track_init(knot_across_track *k, int a, int b, int na, int nb)
{
    memset(k, 0, sizeof *k);
    k->rod[0] = a;
    k->rod[1] = b;
    k->work = malloc((size_t)rod_knot_across_points(na, nb) * 3 * sizeof *k->work);
    k->scratch = rod_knot_scratch_create();
    if (k->work && k->scratch) return 0;
    knot_across_track_release(k);
    return -1;
}

void knot_across_track_release(knot_across_track *k)
{
    free(k->work);
    rod_knot_scratch_destroy(k->scratch);
    k->work = NULL;
    k->scratch = NULL;
}

void knot_across_track_frame(knot_across_track *k, const double *pa, int na, const double *pb,
                             int nb, double t)
{
    const double start = wall_seconds();
    rod_knot now;
    char err[200];
    if (rod_knot_identify_across(k->scratch, pa, na, pb, nb, k->work, &now, err, sizeof err)) {
        if (!k->failures++)
            snprintf(k->failure, sizeof k->failure, "at t = %g s: %s", t, err);
    } else {
        if (k->frames == 0) {
            k->first = now;
            k->first_time = t;
        } else if (!knot_track_same(&now, &k->last) &&
                   k->changes++ < SUMMARY_MAX_KNOT_CHANGES) {
            summary_knot_change *c = &k->change[k->changes - 1];
            c->t = t;
            snprintf(c->type, sizeof c->type, "%s", now.name);
        }
        k->last = now;
        k->last_time = t;
        k->frames++;
    }
    k->seconds += wall_seconds() - start;
}

void knot_across_track_print(FILE *f, const knot_across_track *k, const char *name_a,
                             const char *name_b)
{
    if (k->frames > 0) {
        char poly[128];
        rod_knot_polynomial_text(&k->last, poly, sizeof poly);
        if (k->changes == 0)
            fprintf(f, "  knot across rods %s and %s: %s at t = %g s and at t = %g s, the same in "
                       "all %d output frames (Alexander polynomial %s, determinant %lld, "
                       "signature %d%s)\n", name_a, name_b, k->first.name, k->first_time,
                    k->last_time, k->frames, poly, k->last.determinant, k->last.signature,
                    k->last.has_signature ? "" : " not computed");
        else
            fprintf(f, "  knot across rods %s and %s: %s at t = %g s, %s at t = %g s (Alexander "
                       "polynomial %s, determinant %lld, signature %d): CHANGED %d time%s over "
                       "%d output frames, first at t = %g s to %s\n", name_a, name_b,
                    k->first.name, k->first_time, k->last.name, k->last_time, poly,
                    k->last.determinant, k->last.signature, k->changes,
                    k->changes == 1 ? "" : "s", k->frames, k->change[0].t, k->change[0].type);
        fprintf(f, "        (the two closed into one curve, each end joined far outside to the "
                   "other rod's end on its side); %.3g ms per output frame\n",
                1e3 * k->seconds / (k->frames + k->failures));
    }
    if (k->failures)
        fprintf(f, "  knot across rods %s and %s: not identified in %d output frames, first %s\n",
                name_a, name_b, k->failures, k->failure);
}

void knot_across_track_fill(const knot_across_track *k, summary_rod_knot *out)
{
    const rod_knot *last = &k->last;
    snprintf(out->type, sizeof out->type, "%s", last->name);
    out->terms = last->terms < 32 ? last->terms : 32;
    for (int i = 0; i < out->terms; i++) out->alexander[i] = last->coefficient[i];
    out->determinant = last->determinant;
    out->has_signature = last->has_signature;
    out->signature = last->signature;
    out->rope_d = NAN;
    out->change_count = k->changes < SUMMARY_MAX_KNOT_CHANGES ? k->changes
                                                              : SUMMARY_MAX_KNOT_CHANGES;
    memcpy(out->changes, k->change, sizeof out->changes);
}
