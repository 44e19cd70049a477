/* live_realtime.h: `rodsim live --realtime`'s set-up, shared by the
 * sessions of one rod (live.h) and of several (live_rods.h): the heap
 * reserved and kept, the memory locked, a real-time priority, one CPU. */
#ifndef RODSIM_CLI_LIVE_REALTIME_H
#define RODSIM_CLI_LIVE_REALTIME_H

#include <stddef.h>

/* --realtime: reserves a heap of heap_bytes (live_heap_bytes) that the
 * session's later allocations take without a page fault, locks the memory,
 * takes a real-time priority (SCHED_FIFO 10) and pins the process to its
 * CPU; what is not permitted is said on standard error and the session
 * goes on without it. */
void live_realtime_setup(size_t heap_bytes);
/* The heap a session of rods of `nodes` nodes in all reserves: what the
 * self-contact's columns may grow to (sim/contact/self_contact.h), twice
 * (a realloc holds the old block while it copies), and LIVE_HEAP_BASE. */
size_t live_heap_bytes(long nodes);

#endif
