/* test_worker.c: a worker started with worker_begin dies with its parent,
 * whatever kills the parent (SIGTERM, kill -9), and a worker whose parent
 * is already gone ends at once. The parent here is a forked intermediate
 * process, the test its subreaper, so the orphaned worker is reaped here and
 * its cause of death read. Deterministic: the worker would sleep 60 s. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
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

int main(void)
{
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
