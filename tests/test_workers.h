/* test_workers.h: do a command's worker processes die with it? Starts the
 * real rodsim (RODSIM_BIN) in a process group of its own, waits until it has
 * forked a worker, signals the parent alone (SIGTERM, or SIGKILL, which runs
 * no cleanup), and reaps the parent and, as their subreaper, its orphaned
 * workers. Header-only, tests only. */
#ifndef RODSIM_TEST_WORKERS_H
#define RODSIM_TEST_WORKERS_H

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

typedef struct worker_kill_result {
    int parent_status; /* raw wait status of rodsim; -1 when it could not be started */
    int workers;       /* worker processes alive when the parent was signalled */
    int killed;        /* of them, reaped killed by SIGKILL (dying with the parent) */
    int ended;         /* reaped otherwise: they ran on after the parent's death */
    int survived;      /* still running `deadline_s` after the parent died (then killed) */
} worker_kill_result;

/* Children of `pid`, read from /proc/N/stat (its 4th field is the parent). */
static inline int test_count_children(pid_t pid)
{
    DIR *d = opendir("/proc");
    if (!d) return 0;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] < '0' || e->d_name[0] > '9') continue;
        char path[300], text[512];
        snprintf(path, sizeof path, "/proc/%s/stat", e->d_name);
        FILE *f = fopen(path, "r");
        if (!f) continue;
        size_t got = fread(text, 1, sizeof text - 1, f);
        fclose(f);
        text[got] = '\0';
        const char *close_paren = strrchr(text, ')'); /* the name may hold spaces */
        char state;
        int ppid;
        if (close_paren && sscanf(close_paren + 1, " %c %d", &state, &ppid) == 2 && ppid == pid &&
            state != 'Z')
            n++;
    }
    closedir(d);
    return n;
}

static inline void test_sleep_ms(int ms)
{
    struct timespec t = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}

/* Runs RODSIM_BIN args (NULL-terminated, without argv[0]) with $TMPDIR set to
 * tmpdir (when not NULL), output discarded; once it has a worker, sends `sig`
 * to the parent only and fills *r. The deadlines bound a hang; no result
 * depends on how fast anything runs. */
static inline void test_kill_parent_of_workers(const char *const *args, const char *tmpdir,
                                               int sig, int deadline_s, worker_kill_result *r)
{
    memset(r, 0, sizeof *r);
    r->parent_status = -1;
    prctl(PR_SET_CHILD_SUBREAPER, 1); /* orphaned workers become our children */
    const char *argv[64];
    int n = 0;
    argv[n++] = RODSIM_BIN;
    for (int i = 0; args[i] && n < 63; i++) argv[n++] = args[i];
    argv[n] = NULL;
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        setpgid(0, 0);
        int null = open("/dev/null", O_WRONLY);
        if (null >= 0) {
            dup2(null, 1);
            dup2(null, 2);
        }
        if (tmpdir) setenv("TMPDIR", tmpdir, 1);
        execv(RODSIM_BIN, (char *const *)argv);
        _exit(127);
    }
    if (pid < 0) return;
    setpgid(pid, pid); /* either side may run first */
    for (int waited = 0; waited < 60000 && (r->workers = test_count_children(pid)) == 0;
         waited += 10) {
        if (waitpid(pid, &r->parent_status, WNOHANG) == pid) return; /* ended first */
        test_sleep_ms(10);
    }
    /* let the workers reach their first line (prctl) before the parent dies:
     * a worker forked but not yet running cannot have asked to die with it */
    test_sleep_ms(300);
    r->workers = test_count_children(pid);
    kill(pid, sig);
    while (waitpid(pid, &r->parent_status, 0) < 0 && errno == EINTR) {}
    int reaped = 0;
    for (int waited = 0; reaped < r->workers && waited < deadline_s * 1000; ) {
        int status;
        pid_t child = waitpid(-1, &status, WNOHANG);
        if (child > 0) {
            reaped++;
            if (WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) r->killed++;
            else r->ended++;
        } else if (child == 0) {
            test_sleep_ms(10);
            waited += 10;
        } else {
            break;
        }
    }
    r->survived = r->workers - reaped;
    if (r->survived > 0) { /* clean up what the command failed to */
        kill(-pid, SIGKILL);
        while (waitpid(-1, NULL, 0) > 0 || errno == EINTR) {}
    }
}

#endif
