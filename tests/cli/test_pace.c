/* test_pace.c: the run's revised estimate (cli/run.h) against the time
 * limit, on steps whose CPU cost the test makes by burning the process's
 * CPU clock. Limit 1 s, 10,000 steps: a stretch is 200 steps or 2.8 ms of
 * CPU. One slow step (50 ms) among fast ones gives one revision over the
 * limit (the steps left at the stretch's rate: about 2.2 s) and the run
 * goes on; steps that stay slow (1 ms each, 10 s in all) are stopped at the
 * second revision in a row over the limit, within two stretches;
 * --allow-long (keep_going) revises and never stops. */
#include <stdio.h>
#include <time.h>

#include "cli/run.h"
#include "test.h"

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void burn(double seconds)
{
    const double end = cpu_now() + seconds;
    volatile double x = 0.0;
    while (cpu_now() < end) x += 1.0;
}

static double highest;
static void note_revision(void *context, const run_pace *pace)
{
    (void)context;
    if (pace->estimate > highest) highest = pace->estimate;
}

/* Runs 10,000 steps, step k costing cost(k) s of CPU, checked as
 * run_simulate_paced checks; the step count at which it stopped, or 0. */
static long long run_steps(double (*cost)(long long), int keep_going, run_pace *pace)
{
    run_plan plan = {.steps = 10000};
    *pace = (run_pace){.limit = 1.0, .keep_going = keep_going, .on_revise = note_revision};
    highest = 0.0;
    run_pace_start(pace, &plan);
    for (long long k = 1; k <= plan.steps; k++) {
        burn(cost(k));
        if (k >= pace->next_check && run_pace_check(pace, k)) return k;
    }
    return 0;
}

static double one_slow_step(long long k) { return k == 1000 ? 0.05 : 0.0; }
static double slow_from_1000(long long k) { return k >= 1000 ? 0.001 : 0.0; }

int main(void)
{
    run_pace pace;
    long long stopped = run_steps(one_slow_step, 0, &pace);
    check(stopped == 0 && highest > pace.limit && pace.over == 0,
          "one 50 ms step among fast ones: a revision of %.2f s passes the 1 s limit, the run "
          "goes on to its end (stopped at step %lld; 0 = never; %d revisions)",
          highest, stopped, pace.revisions);
    stopped = run_steps(slow_from_1000, 0, &pace);
    check(stopped > 1000 && stopped <= 1400 && pace.stopped && pace.over == RUN_PACE_OVER,
          "1 ms steps from step 1000 (10 s left): stopped at step %lld (want 1001-1400: at "
          "most two stretches of 200 steps after they begin), at "
          "%d revisions in a row over the limit, the last %.2f s", stopped, pace.over,
          pace.estimate);
    stopped = run_steps(slow_from_1000, 1, &pace);
    check(stopped == 0 && !pace.stopped && highest > pace.limit,
          "the same with --allow-long: revised to %.2f s, never stopped (stopped at step %lld)",
          highest, stopped);
    return test_finish();
}
