/* test_process.h: helpers for tests that drive the real rodsim binary and
 * look at what it wrote: run it capturing its output, write a file into a
 * scratch directory, count its entries (test.h removes it). Header-only,
 * tests only. */
#ifndef RODSIM_TEST_PROCESS_H
#define RODSIM_TEST_PROCESS_H

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "test.h" /* test_remove_tree */

/* Runs RODSIM_BIN with args (NULL-terminated, without argv[0]); its stdout
 * and stderr go to `output`. When seconds > 0 the run is killed (SIGALRM)
 * after that long, so a run that never ends fails the test instead of
 * hanging it. Returns the exit status, -1 when it did not exit. */
static inline int test_run_rodsim_within(const char *const *args, unsigned seconds, char *output,
                                         size_t outlen)
{
    char log_path[] = "/tmp/rodsim_test_outputXXXXXX";
    int fd = mkstemp(log_path);
    if (fd < 0) return -1;
    const char *argv[64];
    int n = 0;
    argv[n++] = RODSIM_BIN;
    for (int i = 0; args[i] && n < 63; i++) argv[n++] = args[i];
    argv[n] = NULL;
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        dup2(fd, 1);
        dup2(fd, 2);
        close(fd);
        if (seconds > 0) alarm(seconds); /* survives execv */
        execv(RODSIM_BIN, (char *const *)argv);
        _exit(127);
    }
    close(fd);
    int status = 0;
    int waited = pid > 0 && waitpid(pid, &status, 0) == pid;
    output[0] = '\0';
    FILE *f = fopen(log_path, "r");
    if (f) {
        size_t got = fread(output, 1, outlen - 1, f);
        output[got] = '\0';
        fclose(f);
    }
    unlink(log_path);
    if (!waited) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static inline int test_run_rodsim(const char *const *args, char *output, size_t outlen)
{
    return test_run_rodsim_within(args, 0, output, outlen);
}

/* Entries of a directory other than . and ..; -1 when it does not exist. */
/* Writes text to the file `name` in directory dir (a scene, a path); a
 * file that cannot be written shows when the test reads it back. */
static inline void test_write_in(const char *dir, const char *name, const char *text)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static inline int test_dir_entries(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) n++;
    closedir(d);
    return n;
}

#endif
