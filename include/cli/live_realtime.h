/* live_realtime.h: the time of `rodsim live`, shared by the sessions of
 * one rod (live.h) and of several (live_rods.h): --realtime's set-up (the
 * heap reserved and kept, the memory locked, a real-time priority, one
 * CPU), the wall clock and the wait for a line's t on it, and the stop
 * signals that end a session like the end of input. */
#ifndef RODSIM_CLI_LIVE_REALTIME_H
#define RODSIM_CLI_LIVE_REALTIME_H

#include <signal.h>
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

/* Set by SIGINT and SIGTERM once live_stop_signals_install has run: the
 * signal's number, else 0. Read between lines, within a line's steps and
 * after a --realtime wait. */
extern volatile sig_atomic_t live_stop_signal;

/* SIGINT and SIGTERM set live_stop_signal (no SA_RESTART: a read or a wait
 * returns at once); SIGPIPE is ignored (a closed standard output is an
 * error of the write). */
void live_stop_signals_install(void);

/* --realtime: waits until t (s from the wall time wall_origin, s) on the
 * wall clock; a stop signal ends the wait. */
void live_pace(double wall_origin, double t);

#endif
