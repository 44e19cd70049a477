/* frame_schedule.c: output times with slow motion (frame_schedule.h). */
#include "cli/frame_schedule.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

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
