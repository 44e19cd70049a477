/* test_clocks.c: the clocks in seconds (base/clocks.h): the wall clock
 * never goes back and counts a sleep in full; the thread's CPU clock
 * advances while it computes, and the process's counts that too. */
#include <time.h>

#include "base/clocks.h"
#include "test.h"

int main(void)
{
    double last = wall_seconds(), back = 0.0;
    for (int i = 0; i < 10000; i++) {
        const double now = wall_seconds();
        if (now < last) back = fmax(back, last - now);
        last = now;
    }
    check(back == 0.0, "the wall clock never goes back over 10000 readings (at most %.3g s)",
          back);
    const double asleep = 0.02; /* s */
    const double before = wall_seconds();
    const struct timespec pause = {0, 20000000L};
    while (nanosleep(&pause, NULL) != 0) {
    }
    const double slept = wall_seconds() - before;
    check(slept >= asleep, "a 20 ms sleep: the wall clock advanced %.6g s, at least %.6g s",
          slept, asleep);
    /* computing until the thread's CPU clock says 20 ms: ends, and the
     * process's clock (every thread) advanced as much (the kernel sums
     * the threads' clocks at its own moments: within 1 ms) */
    const double thread0 = thread_cpu_seconds(), process0 = cpu_seconds();
    volatile double sink = 0.0;
    double thread_used = 0.0;
    while (thread_used < asleep) {
        for (int i = 0; i < 100000; i++) sink = sink + 1e-9 * i;
        thread_used = thread_cpu_seconds() - thread0;
    }
    const double process_used = cpu_seconds() - process0;
    check(process_used >= thread_used - 1e-3,
          "20 ms of computing: the thread's CPU %.6g s, the process's %.6g s (not less, "
          "within 1 ms)", thread_used, process_used);
    return test_finish();
}
