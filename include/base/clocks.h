/* clocks.h: the clocks that time runs, steps and frames, in seconds (s)
 * from an arbitrary origin: only differences mean anything. */
#ifndef RODSIM_CLOCKS_H
#define RODSIM_CLOCKS_H

/* s of wall time, monotonic (CLOCK_MONOTONIC: never set back) */
double wall_seconds(void);

/* s of CPU the process has used, all its threads (CLOCK_PROCESS_CPUTIME_ID:
 * a busy machine does not make a measure look slower) */
double cpu_seconds(void);

/* s of CPU the calling thread has used (CLOCK_THREAD_CPUTIME_ID) */
double thread_cpu_seconds(void);

#endif
