/* worker.c: see worker.h. */
#include "base/worker.h"

#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

void worker_begin(pid_t parent)
{
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(1); /* the parent died before prctl */
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
}

/* A running worker: its process, the read end of its pipe, what it sent. */
typedef struct slot {
    int task;
    pid_t pid;   /* 0: free */
    int fd;      /* -1 once the pipe has closed */
    char *bytes; /* received so far, '\0'-terminated */
    size_t length, capacity;
} slot;

/* Task `task` in this process: run into memory, then done. */
static int run_here(const worker_pool *pool, int task, char *err, size_t errlen)
{
    char *bytes = NULL;
    size_t n = 0;
    FILE *out = open_memstream(&bytes, &n);
    if (!out) {
        snprintf(err, errlen, "out of memory for task %d's result", task);
        return -1;
    }
    int rc = pool->run(pool->context, task, out);
    if (fclose(out) != 0 || !bytes) {
        free(bytes);
        snprintf(err, errlen, "out of memory for task %d's result", task);
        return -1;
    }
    int stop = pool->done(pool->context, task, bytes, n, rc == 0 ? 0 : 1 << 8 /* exit 1 */);
    free(bytes);
    return stop ? 1 : 0;
}

/* Reads what the worker has sent; closes the pipe at its end. -1: out of memory. */
static int receive(slot *s)
{
    if (s->capacity - s->length < 4096) {
        size_t capacity = s->capacity ? 2 * s->capacity : 16384;
        char *grown = realloc(s->bytes, capacity);
        if (!grown) return -1;
        s->bytes = grown;
        s->capacity = capacity;
    }
    ssize_t n = read(s->fd, s->bytes + s->length, s->capacity - s->length - 1);
    if (n > 0) {
        s->length += (size_t)n;
    } else if (n == 0 || errno != EINTR) {
        close(s->fd);
        s->fd = -1;
    }
    s->bytes[s->length] = '\0';
    return 0;
}

/* Starts task `task` in a worker in slot `s`: 0, or -1 when no pipe or
 * process could be had. */
static int start(const worker_pool *pool, slot *slots, int nslots, slot *s, int task)
{
    int fd[2];
    if (pipe(fd) != 0) return -1;
    fflush(NULL); /* the child must not repeat the parent's buffered output */
    pid_t parent = getpid();
    pid_t pid = fork();
    if (pid == 0) {
        worker_begin(parent); /* dies with its parent */
        close(fd[0]);
        for (int i = 0; i < nslots; i++) /* other workers' pipes */
            if (slots[i].pid > 0 && slots[i].fd >= 0) close(slots[i].fd);
        FILE *out = fdopen(fd[1], "w");
        int rc = !out || pool->run(pool->context, task, out);
        if (out && fclose(out) != 0) rc = 1;
        fflush(NULL);
        _exit(rc ? 1 : 0);
    }
    close(fd[1]);
    if (pid < 0) {
        close(fd[0]);
        return -1;
    }
    *s = (slot){.task = task, .pid = pid, .fd = fd[0]};
    return 0;
}

int worker_pool_run(const worker_pool *pool, const int *tasks, int count, char *err,
                    size_t errlen)
{
    if (pool->jobs <= 1) {
        for (int k = 0; k < count; k++) {
            int rc = run_here(pool, tasks ? tasks[k] : k, err, errlen);
            if (rc) return rc;
        }
        return 0;
    }
    int nslots = pool->jobs < count ? pool->jobs : count;
    slot *slots = calloc((size_t)(nslots > 0 ? nslots : 1), sizeof *slots);
    struct pollfd *polls = calloc((size_t)(nslots > 0 ? nslots : 1), sizeof *polls);
    int *polled = calloc((size_t)(nslots > 0 ? nslots : 1), sizeof *polled);
    if (!slots || !polls || !polled) {
        free(slots);
        free(polls);
        free(polled);
        snprintf(err, errlen, "out of memory for %d workers", nslots);
        return -1;
    }
    int next = 0, running = 0, rc = 0;
    while (rc == 0 && (next < count || running > 0)) {
        /* fill the free slots; with none running and none startable, run here */
        while (next < count && running < nslots) {
            int s = 0;
            while (slots[s].pid > 0) s++;
            int task = tasks ? tasks[next] : next;
            if (start(pool, slots, nslots, &slots[s], task) == 0) {
                next++;
                running++;
                continue;
            }
            if (running > 0) break; /* try again when one ends */
            next++;
            rc = run_here(pool, task, err, errlen);
            if (rc) break;
        }
        if (rc || running == 0) continue;
        /* drain every open pipe (a worker blocks when its pipe is full),
         * then reap the workers whose pipes have closed */
        int watched = 0;
        for (int s = 0; s < nslots; s++)
            if (slots[s].pid > 0 && slots[s].fd >= 0) {
                polls[watched] = (struct pollfd){.fd = slots[s].fd, .events = POLLIN};
                polled[watched++] = s;
            }
        if (watched > 0 && poll(polls, (nfds_t)watched, -1) < 0) {
            if (errno == EINTR) continue;
            snprintf(err, errlen, "waiting for the workers: %s", strerror(errno));
            rc = -1;
            break;
        }
        for (int w = 0; w < watched && rc == 0; w++)
            if (polls[w].revents && receive(&slots[polled[w]])) {
                snprintf(err, errlen, "out of memory for the workers' results");
                rc = -1;
            }
        for (int s = 0; s < nslots && rc == 0; s++) {
            slot *sl = &slots[s];
            if (sl->pid <= 0 || sl->fd >= 0) continue;
            int status = 0;
            pid_t got;
            while ((got = waitpid(sl->pid, &status, 0)) < 0 && errno == EINTR) {}
            if (got < 0) status = 1 << 8; /* already reaped elsewhere: no result */
            int stop = pool->done(pool->context, sl->task, sl->bytes ? sl->bytes : "",
                                  sl->length, status);
            free(sl->bytes);
            *sl = (slot){.fd = -1};
            running--;
            if (stop) rc = 1;
        }
    }
    /* stopped, or an error: end the workers still running */
    for (int s = 0; s < nslots; s++) {
        if (slots[s].pid > 0) {
            kill(slots[s].pid, SIGKILL);
            while (waitpid(slots[s].pid, NULL, 0) < 0 && errno == EINTR) {}
        }
        if (slots[s].pid > 0 && slots[s].fd >= 0) close(slots[s].fd);
        free(slots[s].bytes);
    }
    free(slots);
    free(polls);
    free(polled);
    return rc;
}
