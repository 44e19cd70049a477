/* knot_track.c: see knot_track.h. */
#include "cli/knot_track.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/clocks.h"
#include "sim/rod_grid.h"

void knot_track_init(knot_track *k, int nodes)
{
    memset(k, 0, sizeof *k);
    k->scratch = rod_knot_scratch_create();
    k->touch_lo = k->touch_hi = -1;
    k->slip_end = k->tie_end = k->last_end = -1;
    k->prev_pos = malloc((size_t)nodes * 3 * sizeof(double));
}

void knot_track_release(knot_track *k)
{
    rod_knot_scratch_destroy(k->scratch);
    free(k->prev_pos);
    k->scratch = NULL;
    k->prev_pos = NULL;
}

int knot_track_same(const rod_knot *a, const rod_knot *b)
{
    /* the signature too: a trefoil turning into its mirror image is a change */
    return a->terms == b->terms &&
           memcmp(a->coefficient, b->coefficient, (size_t)a->terms * sizeof a->coefficient[0]) == 0 &&
           a->has_signature == b->has_signature && a->signature == b->signature;
}

/* Within how many segments of an end touching strands mean that a knot
 * that comes undone slipped off that end: a few diameters of arc, never
 * fewer than the proximity skip's 5 segments (a loop closing over an end
 * node touches that far from it at the last frame before), and as far as
 * the strands can have slid along each other between the two frames (at
 * most twice the largest node motion: a frame rate low for the motion
 * would otherwise call a slip a pass-through). */
static int slip_reach(const rod_model *m, double moved)
{
    int reach = (int)ceil(3.0 * m->diameter / m->ds);
    int slid = (int)fmin(ceil(2.0 * moved / m->ds) + 1.0, (double)m->nodes);
    if (slid > reach) reach = slid;
    return reach < 6 ? 6 : reach;
}

/* The largest node motion since the last frame (m), from the positions
 * kept then (0 at the first frame, or when they could not be kept). */
static double frame_motion(const knot_track *k, const rod_state *s)
{
    double moved = 0.0;
    /* a cut that took the root's side moved the nodes down (sim/cut.h) */
    const int shift = s->first_node - k->prev_first;
    if (shift < 0) return 0.0; /* the whole thread again: no last frame to compare */
    for (int i = 0; k->prev_pos && k->frames > 0 && i < s->nodes; i++) {
        const double *a = &s->position[3 * i], *b = &k->prev_pos[3 * (i + shift)];
        const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
        moved = fmax(moved, sqrt(dx * dx + dy * dy + dz * dz));
    }
    return moved;
}

static void track_touch(knot_track *k, const rod_state *s)
{
    if (k->prev_pos) memcpy(k->prev_pos, s->position, (size_t)s->nodes * 3 * sizeof(double));
    k->prev_first = s->first_node;
    k->touch_lo = k->touch_hi = -1;
    for (int i = 0; i < s->nodes; i++) {
        const double *f = &s->self_force[3 * i];
        if (f[0] == 0.0 && f[1] == 0.0 && f[2] == 0.0) continue;
        if (k->touch_lo < 0) k->touch_lo = i;
        k->touch_hi = i;
    }
    k->touch_time = s->time;
}

/* The knot of an open centreline: the radial closure's when the other
 * closures (knot.h) give the same knot, else KNOT_FORMING (no polynomial:
 * terms 0, determinant 0, no signature). A closure whose identification
 * fails is left out; the radial one's failure is the frame's. */
static int identify_open(knot_track *k, const rod_state *s, rod_knot *now, char *err,
                         size_t errlen)
{
    if (rod_knot_identify_in(k->scratch, s->position, s->nodes, 0, now, err, errlen)) return -1;
    for (int c = ROD_KNOT_CLOSE_RADIAL + 1; c < ROD_KNOT_CLOSURES; c++) {
        rod_knot other;
        char why[200];
        if (rod_knot_identify_closure(k->scratch, s->position, s->nodes, c, &other, why,
                                      sizeof why))
            continue;
        if (!knot_track_same(now, &other)) {
            memset(now, 0, sizeof *now);
            snprintf(now->name, sizeof now->name, "%s", KNOT_FORMING);
            return 0;
        }
    }
    return 0;
}

int knot_track_is_forming(const rod_knot *k)
{
    return strcmp(k->name, KNOT_FORMING) == 0;
}

/* The end near which strands touched in the frame before (0 root, 1 tip,
 * -1 neither: an end is a point a loop can pass over) and how far from it
 * (segments); the root when within reach of both (an instrument tie draws
 * the held tail, the root, through the loop while the long end lies in
 * touching turns near the tip) */
/* Whether node `node` (the count segments from end `which`'s node) lies
 * within slip_reach of that end; on a graded grid by arc length from the
 * end: as the uniform count ceil(x / ds) >= count, the node count - 1 from
 * the end less than 3 d or that count - 2 less than twice moved along it,
 * or at most 6 segments */
static int within_reach(const rod_model *m, double moved, int which, int count)
{
    if (!m->segment_length) return count <= slip_reach(m, moved);
    if (count <= 6) return 1;
    const double length = rod_node_arc(m, m->nodes - 1);
    const int a = which ? m->nodes - 1 - (count - 1) : count - 1;
    const int b = which ? m->nodes - 1 - (count - 2) : count - 2;
    const double arc_a = which ? length - rod_node_arc(m, a) : rod_node_arc(m, a);
    const double arc_b = which ? length - rod_node_arc(m, b) : rod_node_arc(m, b);
    return arc_a < 3.0 * m->diameter || arc_b < 2.0 * moved;
}

static int change_end(const knot_track *k, const rod_model *m, int nodes, int *reach_out)
{
    const int last = nodes - 1;
    if (k->touch_lo >= 0 && within_reach(m, k->moved, 0, k->touch_lo))
        return *reach_out = k->touch_lo, 0;
    if (k->touch_hi >= 0 && within_reach(m, k->moved, 1, last - k->touch_hi))
        return *reach_out = last - k->touch_hi, 1;
    return -1;
}

/* A change of the knot named, from k->named to now at frame s; gap as
 * knot_track_frame's. The rule of KNOT_TIED (knot_track.h): at an end, and
 * more crossings (the identified type's crossing number) than before. */
static void note_change(knot_track *k, const rod_model *m, const rod_knot *now,
                        const rod_state *s, double gap)
{
    const double t = s->time; /* s */
    int reach = 0;
    const int end = change_end(k, m, s->nodes, &reach);
    const int at_end = end >= 0 || !(gap < KNOT_PASS_GAP * m->diameter);
    /* without self-contact a strand may pass through another anywhere:
     * no change is told a tie */
    const int guarded = m->self_contact && m->options.scheme == ROD_SCHEME_IMPLICIT;
    const int how = !at_end ? KNOT_THROUGH
                    : guarded && now->crossing_number > k->named.crossing_number ? KNOT_TIED
                                                                                 : KNOT_SLIPPED;
    k->changes++;
    k->last_how = how;
    k->last_end = at_end ? end : -1;
    if (how == KNOT_TIED) {
        if (k->ties++ == 0) {
            k->tie_time = t;
            snprintf(k->tie_from, sizeof k->tie_from, "%s", k->named.name);
            snprintf(k->tie_to, sizeof k->tie_to, "%s", now->name);
            k->tie_end = end;
        }
        return;
    }
    if (k->changes - k->ties > 1) return;
    k->change_time = t;
    snprintf(k->change_from, sizeof k->change_from, "%s", k->named.name);
    snprintf(k->change_to, sizeof k->change_to, "%s", now->name);
    k->slip_end = end;
    k->slip_reach = reach;
    k->slip_time = k->touch_time;
    k->change_gap = gap;
}

const char *knot_track_how_text(int how, int end)
{
    static const char *const tied[3] = {"tied at an end", "tied at the root end",
                                        "tied at the tip end"};
    static const char *const slipped[3] = {"a loop passed over an end",
                                           "slipped off the root end", "slipped off the tip end"};
    if (how == KNOT_THROUGH || end < -1 || end > 1) return NULL;
    return how == KNOT_TIED ? tied[end + 1] : slipped[end + 1];
}

void knot_track_frame(knot_track *k, const rod_model *m, const rod_state *s, double gap)
{
    double start = wall_seconds();
    rod_knot now;
    char err[200];
    k->moved = frame_motion(k, s);
    if (identify_open(k, s, &now, err, sizeof err)) {
        if (!k->failures++)
            snprintf(k->failure, sizeof k->failure, "at t = %g s: %s", s->time, err);
    } else {
        if (k->frames == 0) {
            k->first = now;
            k->first_time = s->time;
        }
        /* a forming frame is no change: the changes are those of the knot
         * named, from the last frame that named one */
        const int named = !knot_track_is_forming(&now);
        if (named && k->has_named && !knot_track_same(&now, &k->named))
            note_change(k, m, &now, s, gap);
        if (named) k->named = now, k->has_named = 1;
        k->forming += !named;
        k->last = now;
        k->last_time = s->time;
        k->frames++;
    }
    track_touch(k, s);
    k->seconds += wall_seconds() - start;
}

int knot_track_change_is_slip(const knot_track *k, const rod_model *m)
{
    return k->changes > k->ties &&
           (k->slip_end >= 0 || !(k->change_gap < KNOT_PASS_GAP * m->diameter));
}

/* what the rope in a tightened overhand knot is reported against */
#define IDEAL_TREFOIL_ROPELENGTH KNOT_SHORTEST_ROPE

int knot_track_can_knot(const rod_model *m)
{
    return m->self_contact && m->options.scheme == ROD_SCHEME_IMPLICIT &&
           m->length > KNOT_SHORTEST_ROPE * m->diameter;
}

/* A knot named: neither the unknot nor KNOT_FORMING */
static int is_knot(const rod_knot *k)
{
    return strcmp(k->name, "unknot") != 0 && !knot_track_is_forming(k);
}

int knot_track_was_knotted(const knot_track *k)
{
    return k->frames > 0 && (k->changes > 0 || is_knot(&k->first) || is_knot(&k->last));
}

double knot_track_rope(const knot_track *k, const rod_model *m)
{
    if (k->frames == 0 || !is_knot(&k->last) || k->touch_lo < 0 || k->touch_time != k->last_time)
        return NAN;
    /* the arc between the outermost nodes the strands press on */
    if (m->segment_length)
        return (rod_node_arc(m, k->touch_hi) - rod_node_arc(m, k->touch_lo)) / m->diameter;
    return (k->touch_hi - k->touch_lo) * m->ds / m->diameter;
}

/* The changes' line: all of them, the first tie and the first change no
 * tie (in capitals when there was one: a knot tied is no failure) */
static void print_changes(FILE *f, const knot_track *k, const rod_model *m)
{
    const int others = k->changes - k->ties;
    fprintf(f, "        knot: %s at t = %g s, %s at t = %g s: %s %d time%s over %d output frames",
            k->first.name, k->first_time, k->last.name, k->last_time,
            others ? "CHANGED" : "changed", k->changes, k->changes == 1 ? "" : "s", k->frames);
    if (k->ties)
        fprintf(f, ", %s at t = %g s (%s -> %s, %s)", others ? "the first tie" : "first",
                k->tie_time, k->tie_from, k->tie_to, knot_track_how_text(KNOT_TIED, k->tie_end));
    if (others) {
        const char *how = knot_track_how_text(KNOT_SLIPPED, k->slip_end);
        fprintf(f, ", %s at t = %g s (%s -> %s%s%s)",
                k->ties ? "the first change no tie" : "first", k->change_time, k->change_from,
                k->change_to, knot_track_change_is_slip(k, m) ? ", " : "",
                knot_track_change_is_slip(k, m) ? how : "");
    }
    fputc('\n', f);
}

void knot_track_print(FILE *f, const knot_track *k, const rod_model *m)
{
    if (k->frames > 0) {
        char poly[128];
        rod_knot_polynomial_text(&k->first, poly, sizeof poly);
        if (k->changes == 0 && k->forming == 0)
            fprintf(f, "        knot: %s at t = %g s and at t = %g s, the same in all %d output "
                       "frames (Alexander polynomial %s, determinant %lld, signature %d%s)\n",
                    k->first.name, k->first_time, k->last_time, k->frames, poly,
                    k->first.determinant, k->first.signature,
                    k->first.has_signature ? "" : " not computed");
        else if (k->changes == 0)
            fprintf(f, "        knot: %s at t = %g s, %s at t = %g s: forming (the closures of "
                       "its open ends disagree) in %d of %d output frames, no change of the "
                       "knot named\n", k->first.name, k->first_time, k->last.name,
                    k->last_time, k->forming, k->frames);
        else
            print_changes(f, k, m);
        const double rope = knot_track_rope(k, m);
        if (!isnan(rope)) {
            fprintf(f, "        knot: rope in the knot at t = %g s: %.1f diameters, between the "
                       "outermost nodes where strands press on each other", k->last_time, rope);
            if (strncmp(k->last.name, "trefoil", 7) == 0)
                fprintf(f, " (the ideal closed trefoil takes %.2f: %+.0f %%)",
                        IDEAL_TREFOIL_ROPELENGTH,
                        100.0 * (rope - IDEAL_TREFOIL_ROPELENGTH) / IDEAL_TREFOIL_ROPELENGTH);
            fputc('\n', f);
        }
        fprintf(f, "        knot identification: %.3g ms per output frame\n",
                1e3 * k->seconds / (k->frames + k->failures));
    }
    if (k->failures)
        fprintf(f, "        knot: not identified in %d output frames, first %s\n", k->failures,
                k->failure);
}
