/* test_worker.c: a worker started with worker_begin dies with its parent,
 * whatever kills the parent (SIGTERM, kill -9), and a worker whose parent
 * is already gone ends at once. The parent here is a forked intermediate
 * process, the test its subreaper, so the orphaned worker is reaped here and
 * its cause of death read. Deterministic: the worker would sleep 60 s.
 * The pool (worker_pool_run): every task's result arrives whole, whatever
 * its size (1 MiB, over a pipe's buffer) and however many run at once; a
 * failed task and a killed worker are told apart; a stop kills the others. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "base/worker.h"
#include "test.h"

/* Forks an intermediate "parent" that forks a worker (worker_begin, then a
 * long sleep) and tells us its pid; kills the parent with `sig`; returns
 * the worker's wait status (-1 when it could not be reaped within 10 s). */
static int worker_status_after_parent_dies(int sig)
{
    int fd[2];
    if (pipe(fd) != 0) return -1;
    fflush(stdout);
    pid_t parent = fork();
    if (parent == 0) {
        close(fd[0]);
        pid_t me = getpid();
        pid_t worker = fork();
        if (worker == 0) {
            worker_begin(me);
            sleep(60);
            _exit(0);
        }
        /* the worker has called prctl once it is running: let it start */
        struct timespec settle = {0, 200000000L};
        nanosleep(&settle, NULL);
        if (write(fd[1], &worker, sizeof worker) != (ssize_t)sizeof worker) _exit(1);
        pause(); /* until killed */
        _exit(0);
    }
    close(fd[1]);
    pid_t worker = -1;
    ssize_t got = read(fd[0], &worker, sizeof worker);
    close(fd[0]);
    if (got != (ssize_t)sizeof worker) return -1;
    kill(parent, sig);
    waitpid(parent, NULL, 0);
    for (int waited = 0; waited < 10000; waited += 10) {
        int status;
        pid_t r = waitpid(worker, &status, WNOHANG);
        if (r == worker) return status;
        struct timespec step = {0, 10000000L};
        nanosleep(&step, NULL);
    }
    kill(worker, SIGKILL);
    waitpid(worker, NULL, 0);
    return -1;
}

/* ---- the pool ---- */

#define POOL_TASKS 7
typedef struct pool_log {
    int calls[POOL_TASKS]; /* done calls per task */
    int intact[POOL_TASKS];
    int status[POOL_TASKS];
    int other_process[POOL_TASKS]; /* run in a process other than the test's */
    pid_t self;
    int stop_after; /* done returns 1 after this many calls; 0: never */
    int done_calls;
} pool_log;

/* Task k writes its process id, then k + 1 lines of 150 KiB (task 6:
 * 1 MiB in all, over a pipe's 64 KiB), each of the letter 'a' + k; task 3
 * fails (returns 1); task 5 kills itself in a worker. */
static int pool_run(void *context, int task, FILE *out)
{
    pool_log *log = context;
    fprintf(out, "%ld\n", (long)getpid());
    for (int line = 0; line <= task; line++) {
        for (int i = 0; i < 150 * 1024; i++) fputc('a' + task, out);
        fputc('\n', out);
    }
    if (task == 5 && getpid() != log->self) {
        fflush(out);
        raise(SIGKILL);
    }
    if (log->stop_after && task > 0) sleep(60); /* ended by the stop, never by the time */
    return task == 3;
}

static int pool_done(void *context, int task, const char *bytes, size_t n, int status)
{
    pool_log *log = context;
    log->calls[task]++;
    log->status[task] = status;
    long pid = strtol(bytes, NULL, 10);
    log->other_process[task] = pid != (long)log->self;
    const char *body = strchr(bytes, '\n');
    size_t want = (size_t)(task + 1) * (150 * 1024 + 1);
    int intact = body && bytes[n] == '\0' && (size_t)(bytes + n - body - 1) == want;
    for (size_t i = 0; intact && i < want; i++)
        intact = body[1 + i] == ((i + 1) % (150 * 1024 + 1) == 0 ? '\n' : 'a' + task);
    log->intact[task] = intact;
    return log->stop_after && ++log->done_calls >= log->stop_after;
}

static void test_pool(int jobs)
{
    pool_log log = {.self = getpid()};
    worker_pool pool = {.jobs = jobs, .context = &log, .run = pool_run, .done = pool_done};
    char err[256] = "";
    int rc = worker_pool_run(&pool, NULL, POOL_TASKS, err, sizeof err);
    check(rc == 0, "pool, jobs %d: runs %d tasks, returns 0 (%d %s)", jobs, POOL_TASKS, rc, err);
    int once = 1, intact = 1, where = 1;
    for (int k = 0; k < POOL_TASKS; k++) {
        once &= log.calls[k] == 1;
        if (k != 5 || jobs <= 1) intact &= log.intact[k];
        where &= log.other_process[k] == (jobs > 1);
    }
    check(once, "pool, jobs %d: done called once for every task", jobs);
    check(intact, "pool, jobs %d: every result arrives whole (task 6: %d KiB)", jobs,
          7 * 150);
    check(where, "pool, jobs %d: tasks run %s", jobs,
          jobs > 1 ? "in worker processes" : "in this process");
    check(log.status[0] == 0 && log.status[6] == 0 && WIFEXITED(log.status[3]) &&
              WEXITSTATUS(log.status[3]) == 1,
          "pool, jobs %d: status 0 for a task that succeeds, exit 1 for one that fails (%d)",
          jobs, log.status[3]);
    if (jobs > 1)
        check(WIFSIGNALED(log.status[5]) && WTERMSIG(log.status[5]) == SIGKILL,
              "pool, jobs %d: a worker killed by a signal is reported as killed (status %d)",
              jobs, log.status[5]);
    check(waitpid(-1, NULL, WNOHANG) < 0 && errno == ECHILD,
          "pool, jobs %d: no worker left behind", jobs);
}

/* done stops the pool after the first task (which does not sleep): the
 * others (which would sleep 60 s) are killed and reaped. */
static void test_pool_stop(void)
{
    pool_log log = {.self = getpid(), .stop_after = 1};
    worker_pool pool = {.jobs = 3, .context = &log, .run = pool_run, .done = pool_done};
    const int tasks[4] = {1, 2, 0, 4};
    char err[256] = "";
    int rc = worker_pool_run(&pool, tasks, 4, err, sizeof err);
    check(rc == 1 && log.calls[0] == 1 && log.calls[1] + log.calls[2] + log.calls[4] == 0,
          "pool stopped by done: returns 1 (%d), only task 0 ended (%d %d %d %d)", rc,
          log.calls[0], log.calls[1], log.calls[2], log.calls[4]);
    check(waitpid(-1, NULL, WNOHANG) < 0 && errno == ECHILD,
          "pool stopped by done: the running workers were killed and reaped");
}

int main(void)
{
    test_pool(1);
    test_pool(3);
    test_pool_stop();
    prctl(PR_SET_CHILD_SUBREAPER, 1); /* orphaned workers become our children */
    const int signals[2] = {SIGTERM, SIGKILL};
    for (int k = 0; k < 2; k++) {
        int status = worker_status_after_parent_dies(signals[k]);
        check(status != -1 && WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL,
              "worker_begin: the worker dies (SIGKILL) within 10 s of its parent's %s "
              "(status %s %d)", signals[k] == SIGTERM ? "SIGTERM" : "kill -9",
              status == -1 ? "none" : WIFSIGNALED(status) ? "signal" : "exit",
              status == -1 ? 0 : WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));
    }
    /* a parent that is gone before the worker starts: the worker ends at once */
    fflush(stdout);
    pid_t child = fork();
    if (child == 0) {
        worker_begin((pid_t)-1); /* never a parent's pid */
        sleep(60);
        _exit(0);
    }
    int status = 0;
    waitpid(child, &status, 0);
    check(WIFEXITED(status) && WEXITSTATUS(status) == 1,
          "worker_begin with a parent that is not the worker's: exits 1 at once (exit %d)",
          WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    return test_finish();
}
