/* test.h: the test harness. Every check prints one line; a validation prints
 * the computed value, the reference and the relative error. A test program
 * ends with `return test_finish();`, which prints "N passed, N failed" and
 * removes the test's temporary folder (test_dir). */
#ifndef RODSIM_TEST_H
#define RODSIM_TEST_H

#include <dirent.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

static int test_passed_count, test_failed_count;

/* The test's temporary folder ("" until test_dir makes it), the process
 * that made it, and the paths test_path handed out (freed by test_finish). */
static char test_dir_name[64];
static pid_t test_dir_owner;
static char **test_paths;
static size_t test_path_count, test_path_capacity;

static inline int test_record(int ok)
{
    if (ok) test_passed_count++; else test_failed_count++;
    return ok;
}

/* A property check: prints PASS/FAIL and the message. */
static inline int check(int ok, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static inline int check(int ok, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    printf("%s ", ok ? "PASS" : "FAIL");
    vprintf(fmt, ap);
    printf("\n");
    va_end(ap);
    fflush(stdout);
    return test_record(ok);
}

/* |computed - reference| <= tol * |reference| */
static inline int check_rel(const char *what, double computed, double reference, double tol)
{
    double err = fabs(computed - reference) / fabs(reference);
    int ok = isfinite(computed) && err <= tol;
    return check(ok, "%s: computed %.9g, reference %.9g, relative error %.3e (tolerance %.1e)",
                 what, computed, reference, err, tol);
}

/* |computed - reference| <= tol */
static inline int check_abs(const char *what, double computed, double reference, double tol)
{
    double err = fabs(computed - reference);
    int ok = isfinite(computed) && err <= tol;
    return check(ok, "%s: computed %.9g, reference %.9g, absolute error %.3e (tolerance %.1e)",
                 what, computed, reference, err, tol);
}

/* Removes a directory and everything below it. */
static inline void test_remove_tree(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) return;
    struct dirent *e;
    char path[1400];
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        if (snprintf(path, sizeof path, "%s/%s", dir, e->d_name) >= (int)sizeof path) continue;
        if (unlink(path)) test_remove_tree(path);
    }
    closedir(d);
    rmdir(dir);
}

/* Removes the test's temporary folder (test_dir) and frees the paths
 * test_path handed out: test_finish calls it, a benchmark at its end. */
static inline void test_dir_remove(void)
{
    if (test_dir_name[0] && test_dir_owner == getpid()) {
        if (getenv("RODSIM_TEST_KEEP"))
            printf("kept %s\n", test_dir_name); /* to look at what the test wrote */
        else
            test_remove_tree(test_dir_name);
        test_dir_name[0] = '\0';
    }
    for (size_t i = 0; i < test_path_count; i++) free(test_paths[i]);
    free(test_paths);
    test_paths = NULL;
    test_path_count = test_path_capacity = 0;
}

static inline int test_finish(void)
{
    printf("%d passed, %d failed\n", test_passed_count, test_failed_count);
    test_dir_remove();
    return test_failed_count ? 1 : 0;
}

/* Stops the test with one failure (a setup it cannot go on without). */
static inline void test_abort(const char *what)
{
    check(0, "%s", what);
    exit(test_finish());
}

/* The test's own temporary folder, made (mkdtemp) on first use, so two
 * suites on one machine never write the same file; test_finish removes it
 * with everything in it (RODSIM_TEST_KEEP set in the environment: keeps
 * it, and prints its name). Also in the environment as RODSIM_TEST_DIR,
 * for the shell commands a test gives to system(). */
static inline const char *test_dir(void)
{
    if (!test_dir_name[0]) {
        strcpy(test_dir_name, "/tmp/rodsim_test_XXXXXX");
        if (!mkdtemp(test_dir_name)) {
            test_dir_name[0] = '\0';
            test_abort("the test's temporary folder (mkdtemp in /tmp)");
        }
        test_dir_owner = getpid();
        setenv("RODSIM_TEST_DIR", test_dir_name, 1);
    }
    return test_dir_name;
}

/* test_dir()/name (name may name a subfolder, which the caller makes);
 * the string stays valid until test_finish (or test_dir_remove). */
static inline const char *test_path(const char *name)
{
    const char *folder = test_dir();
    if (test_path_count == test_path_capacity) {
        size_t capacity = test_path_capacity ? 2 * test_path_capacity : 16;
        char **grown = realloc(test_paths, capacity * sizeof *grown);
        if (!grown) test_abort("memory for a temporary path");
        test_paths = grown;
        test_path_capacity = capacity;
    }
    size_t len = strlen(folder) + 1 + strlen(name) + 1;
    char *path = malloc(len);
    if (!path) test_abort("memory for a temporary path");
    snprintf(path, len, "%s/%s", folder, name);
    test_paths[test_path_count++] = path;
    return path;
}

/* 1 when the scene file is a beam FEM scene (rodsim fem: it has a [material]
 * section); rod scenes (rodsim run) do not. */
static inline int test_is_fem_scene(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f) return 0;
    char line[512];
    int fem = 0;
    while (!fem && fgets(line, sizeof line, f)) fem = strncmp(line, "[material]", 10) == 0;
    fclose(f);
    return fem;
}

/* 1 under the sanitizer build (tests may shorten long runs there). */
static inline int test_sanitized(void)
{
    const char *f = getenv("RODSIM_TEST_FLAVOUR");
    return f && f[0] == 'a';
}

#endif
