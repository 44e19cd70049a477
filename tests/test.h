/* test.h: the test harness. Every check prints one line; a validation prints
 * the computed value, the reference and the relative error. A test program
 * ends with `return test_finish();`, which prints "N passed, N failed". */
#ifndef RODSIM_TEST_H
#define RODSIM_TEST_H

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int test_passed_count, test_failed_count;

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

static inline int test_finish(void)
{
    printf("%d passed, %d failed\n", test_passed_count, test_failed_count);
    return test_failed_count ? 1 : 0;
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
