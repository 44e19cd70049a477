/* worker.h: forked worker processes (rodsim sweep, figure, validate and
 * stability run their points in children that send their results back
 * through a pipe): the start of a worker, and the one pool that runs them. */
#ifndef RODSIM_WORKER_H
#define RODSIM_WORKER_H

#include <stddef.h>
#include <stdio.h>
#include <sys/types.h>

/* The most worker processes a command's --jobs N may ask for (sweep,
 * figure, validate, stability alike): each holds a process and a pipe
 * here, and far more than a machine's cores only queue; 1024 workers with
 * their pipes would reach the usual limit of 1024 open files. */
#define WORKER_MAX_JOBS 64

/* Call first in the child of fork(), with the parent's pid taken before the
 * fork. The worker stays in its parent's process group (a Ctrl-C reaches
 * both) and dies with its parent: PR_SET_PDEATHSIG covers SIGTERM and kill -9
 * of the parent, which can run no cleanup; a parent that died before the call
 * ends the worker at once. The parent's signal handlers (which remove the
 * parent's temporary files) are reset to the default. */
void worker_begin(pid_t parent);

/* What a pool runs: tasks, each computed by `run` in a worker process whose
 * output `done` receives in this process. */
typedef struct worker_pool {
    int jobs;      /* worker processes at a time; <= 1: every task here, in order */
    void *context; /* passed to run and done */
    /* Computes task `task`, writing its result to `out`. Runs in a worker
     * (which then exits 1 unless it returns 0), or in this process when
     * jobs <= 1 or no process can be started. Returns 0, or nonzero: failed. */
    int (*run)(void *context, int task, FILE *out);
    /* In this process, as each task ends (in the order they end): `bytes`
     * (n of them, then a '\0'; never NULL) are what run wrote; `status` is 0
     * when run returned 0, else a wait status (WIFSIGNALED: the worker was
     * killed; WEXITSTATUS 1: run failed or the worker could not send). Returns
     * 0 to go on, nonzero to stop: running workers are killed, no task starts. */
    int (*done)(void *context, int task, const char *bytes, size_t n, int status);
} worker_pool;

/* Runs tasks[0 .. count-1] (NULL: the tasks 0 .. count-1), pool->jobs at a
 * time. Every worker's pipe is drained as it writes, so results of any size
 * pass; a worker dies with this process (worker_begin). Returns 0 when every
 * task has ended and been given to done, 1 when done stopped the pool, -1
 * with a message (out of memory, poll failed; the workers are killed). */
int worker_pool_run(const worker_pool *pool, const int *tasks, int count, char *err,
                    size_t errlen);

#endif
