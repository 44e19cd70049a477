/* live_realtime.c: rodsim live's --realtime set-up, clock and stop
 * signals (live_realtime.h). */
#define _GNU_SOURCE /* mlockall flags, sched_setaffinity, clock_nanosleep */
#include "cli/live_realtime.h"

#include <errno.h>
#include <malloc.h> /* mallopt: the heap --realtime keeps */
#include <math.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

#include "sim/contact/self_contact.h"

/* The heap reserved besides the self-contact's columns, bytes: the rest
 * of what a step may allocate on demand (pair lists, a Jacobian's band). */
#define LIVE_HEAP_BASE ((size_t)16 << 20)

size_t live_heap_bytes(long nodes)
{
    /* the pairs' node columns (at most SELF_CONTACT_NODE_SLOTS, 3 each) and
     * their solutions (3 a ranked pair), 6 unknowns a node, doubles */
    const size_t columns = (size_t)3 * (SELF_CONTACT_NODE_SLOTS + SELF_CONTACT_RANK_PAIRS);
    return LIVE_HEAP_BASE + 2 * columns * 6 * (size_t)(nodes > 0 ? nodes : 0) * sizeof(double);
}

/* --realtime: reserves the heap, locks the memory, takes a real-time
 * priority (SCHED_FIFO 10: above every ordinary process, below the
 * kernel's own threads, and the kernel's RT throttling still leaves 5 % of
 * each second to the rest) and pins the process to the CPU it runs on (no
 * migration between lines). The heap: the self-contact grows its columns
 * when strands first touch (a run that never touches holds none), and with
 * the memory locked each new page is faulted in at once: a knot's line
 * that grew them by 1 MB took 0.6 ms of CPU instead of 0.3 (256 faults),
 * its first line 0.7-1.0 ms instead of 0.35. So the heap is grown once,
 * touched, and kept (malloc neither trims it nor maps blocks of its own):
 * later allocations reuse its locked pages. What is not permitted (no
 * CAP_IPC_LOCK or CAP_SYS_NICE) is said, and the session goes on without it. */
void live_realtime_setup(size_t heap_bytes)
{
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, -1);
    char *heap = malloc(heap_bytes);
    if (heap) {
        volatile char *touch = heap;
        for (size_t i = 0; i < heap_bytes; i += 4096) touch[i] = 0;
    }
    free(heap);
    if (mlockall(MCL_CURRENT | MCL_FUTURE))
        fprintf(stderr, "rodsim live: --realtime: could not lock memory (%s); going on\n",
                strerror(errno));
    struct sched_param priority = {.sched_priority = 10};
    if (sched_setscheduler(0, SCHED_FIFO, &priority))
        fprintf(stderr, "rodsim live: --realtime: no real-time priority (%s); going on\n",
                strerror(errno));
    int cpu = sched_getcpu();
    cpu_set_t set;
    CPU_ZERO(&set);
    if (cpu >= 0) CPU_SET(cpu, &set);
    if (cpu < 0 || sched_setaffinity(0, sizeof set, &set))
        fprintf(stderr, "rodsim live: --realtime: not pinned to a CPU (%s); going on\n",
                strerror(errno));
}

volatile sig_atomic_t live_stop_signal;
static void on_stop_signal(int sig) { live_stop_signal = sig; }

void live_stop_signals_install(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    signal(SIGPIPE, SIG_IGN);
}

void live_pace(double wall_origin, double t)
{
    /* t is at most a session's max_ahead steps ahead, but solver.dt may be
     * huge: the wait stays within time_t's range */
    const double due = wall_origin + fmin(t, 1e9);
    struct timespec ts = {(time_t)due, (long)((due - floor(due)) * 1e9)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR &&
           !live_stop_signal) {}
}
