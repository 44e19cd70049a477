/* frame_schedule.c: output times with slow motion (frame_schedule.h). */
#include "cli/frame_schedule.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/rod.h"
#include "sim/rod_grid.h"

/* Regular intervals in duration and whether a partial one ends it (as run.c:
 * to a relative 1e-9, an interval of k / rate is k intervals). */
static double regular_intervals(double duration, int rate, int *partial)
{
    double whole = floor(duration * rate * (1.0 + 1e-12) + 1e-9);
    double rest = duration - whole / rate;
    *partial = rest > 1e-9 * fmax(1.0, duration);
    return whole;
}

/* Range k moved to regular indices [*first, *last] (last > first), with
 * its intervals; 0 when it falls outside the run. */
static int range_indices(const render_slow *s, int rate, double whole, int64_t *first,
                         int64_t *last, int64_t *fine)
{
    double a = fmin(round(s->start * rate), whole), b = fmin(round(s->end * rate), whole);
    if (b <= a) b = a + 1;
    if (b > whole) return 0;
    *first = (int64_t)a;
    *last = (int64_t)b;
    double n = round((b - a) * s->factor);
    *fine = (int64_t)(n < b - a ? b - a : n);
    return 1;
}

int frame_schedule_make(const render_options *o, int rate, double duration, frame_schedule *fs)
{
    memset(fs, 0, sizeof *fs);
    int partial;
    double whole = regular_intervals(duration, rate, &partial);
    double count = whole + 1 + partial;
    int64_t first[RENDER_MAX_SLOW], last[RENDER_MAX_SLOW], fine[RENDER_MAX_SLOW];
    int used[RENDER_MAX_SLOW];
    int64_t previous_end = -1;
    for (int k = 0; k < o->slow_count; k++) {
        used[k] = range_indices(&o->slow[k], rate, whole, &first[k], &last[k], &fine[k]);
        /* two ranges moved onto the same regular time: the later one starts after */
        if (used[k] && first[k] < previous_end) used[k] = 0;
        if (used[k]) {
            count += (double)(fine[k] - (last[k] - first[k]));
            previous_end = last[k];
        }
    }
    if (!(count <= RUN_MAX_COUNT) || count > (double)(SIZE_MAX / sizeof(double))) return -1;
    fs->count = (int64_t)count;
    fs->time = malloc((size_t)fs->count * sizeof(double));
    if (!fs->time) return -1;
    int64_t n = 0, k = 0;
    int range = 0;
    while (k <= (int64_t)whole) {
        while (range < o->slow_count && !used[range]) range++;
        if (range < o->slow_count && k == first[range]) {
            double a = (double)first[range] / rate, span = (double)(last[range] - first[range]) / rate;
            for (int64_t j = 0; j < fine[range]; j++)
                fs->time[n++] = a + span * (double)j / (double)fine[range];
            k = last[range];
            range++;
            continue;
        }
        fs->time[n++] = fmin((double)k / rate, duration);
        k++;
    }
    if (partial) fs->time[n++] = duration;
    fs->count = n;
    return 0;
}

void frame_schedule_release(frame_schedule *fs)
{
    free(fs->time);
    memset(fs, 0, sizeof *fs);
}

void frame_schedule_plan(const frame_schedule *fs, double dt, run_plan *p)
{
    int64_t steps = 0, most = 0;
    double largest = 0;
    for (int64_t k = 1; k < fs->count; k++) {
        double interval = fs->time[k] - fs->time[k - 1];
        int64_t n = run_interval_steps(interval, dt);
        steps += n;
        if (n > most) most = n;
        largest = fmax(largest, interval / (double)n);
    }
    p->frames = fs->count;
    p->frames_estimate = (double)fs->count;
    p->intervals = fs->count - 1;
    p->steps_per_interval = most;
    p->step = largest;
    p->last_interval = 0;
    p->last_steps = 0;
    p->last_step = 0;
    p->steps = steps;
    p->steps_estimate = (double)steps;
    p->frame_times = fs->time;
    p->dt = dt;
}

/* The rope in the knot, frame by frame (m; NAN where no strands press). */
typedef struct rope_series {
    double *time, *rope;
    int64_t count, capacity;
} rope_series;

static int note_rope(void *context, const rod_model *m, const rod_state *s, char *err,
                     size_t errlen)
{
    rope_series *r = context;
    (void)err;
    (void)errlen;
    if (r->count == r->capacity) return 0;
    int lo = -1, hi = -1;
    for (int i = 0; s->self_force && i < s->nodes; i++) {
        const double *f = &s->self_force[3 * i];
        if (f[0] == 0.0 && f[1] == 0.0 && f[2] == 0.0) continue;
        if (lo < 0) lo = i;
        hi = i;
    }
    r->time[r->count] = s->time;
    /* the arc between them: a graded grid's (rod_node_arc), i ds on a uniform one */
    const double rope = m->segment_length ? rod_node_arc(m, hi) - rod_node_arc(m, lo)
                                          : (hi - lo) * m->ds;
    r->rope[r->count] = lo >= 0 && hi > lo ? rope : NAN;
    r->count++;
    return 0;
}

/* The stretch of the series where the rope falls at least half as fast as
 * at its fastest. 1 with *range, 0 when it never falls. */
static int fastest_fall(const rope_series *r, int rate, render_slow *range)
{
    int64_t h = (int64_t)fmax(1.0, round(0.05 * rate)), n = r->count, fastest = -1;
    double *slope = malloc((size_t)(n > 0 ? n : 1) * sizeof *slope);
    if (!slope) return 0;
    double least = 0;
    for (int64_t k = 0; k < n; k++) {
        slope[k] = NAN;
        if (k < h || k + h >= n || isnan(r->rope[k - h]) || isnan(r->rope[k + h])) continue;
        slope[k] = (r->rope[k + h] - r->rope[k - h]) / (r->time[k + h] - r->time[k - h]);
        if (slope[k] < least) least = slope[k], fastest = k;
    }
    int found = fastest >= 0;
    if (found) {
        int64_t a = fastest, b = fastest;
        while (a > 0 && slope[a - 1] <= 0.5 * least) a--;
        while (b + 1 < n && slope[b + 1] <= 0.5 * least) b++;
        range->start = r->time[a > h ? a - h : 0];
        range->end = r->time[b + h < n ? b + h : n - 1];
    }
    free(slope);
    return found;
}

int frame_schedule_find_tightening(const rod_model *m, const run_plan *p, int rate, double factor,
                                   render_slow *range, char *err, size_t errlen)
{
    rod_solver solver = {0};
    rope_series r = {0};
    r.capacity = p->frames;
    r.time = malloc((size_t)r.capacity * sizeof(double));
    r.rope = malloc((size_t)r.capacity * sizeof(double));
    rod_state *s = rod_state_create(m);
    int found = -1;
    if (!r.time || !r.rope || !s) {
        snprintf(err, errlen, "out of memory");
    } else if (rod_solver_init(&solver, m, err, errlen) == 0) {
        rod_report report;
        run_stats stats;
        rod_status st = run_simulate(&solver, m, s, p, rate, note_rope, &r, &report, &stats);
        if (st == ROD_OK) {
            found = fastest_fall(&r, rate, range);
            range->factor = factor;
        } else {
            snprintf(err, errlen, "the first pass stopped at t = %g s: %s", s->time,
                     report.message[0] ? report.message : "the scheme failed");
        }
        rod_solver_release(&solver);
    }
    rod_state_destroy(s);
    free(r.time);
    free(r.rope);
    return found;
}
