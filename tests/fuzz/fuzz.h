/* fuzz.h: shared by the libFuzzer harnesses (tests/fuzz/README in run_fuzz.sh).
 *
 * A harness aborts (a crash for libFuzzer) when a parser breaks its
 * documented contract, not only on memory errors found by ASan/UBSan. */
#ifndef RODSIM_FUZZ_H
#define RODSIM_FUZZ_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A private folder for the harness' files, made once under $TMPDIR (the
 * runner points it into its own temporary folder and removes that). */
static inline const char *fuzz_dir(void)
{
    static char dir[512];
    if (!dir[0]) {
        const char *tmp = getenv("TMPDIR");
        snprintf(dir, sizeof dir, "%s/rodsim-fuzz-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
        if (!mkdtemp(dir)) {
            perror("fuzz: mkdtemp");
            abort();
        }
    }
    return dir;
}

/* The input as a NUL-terminated string (a NUL inside ends it, as it would
 * for the parser reading a file). Caller frees. */
static inline char *fuzz_text(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text) abort();
    memcpy(text, data, size);
    text[size] = '\0';
    return text;
}

/* Aborts with the message when a contract does not hold. */
static inline void fuzz_require(int ok, const char *what, const char *detail)
{
    if (ok) return;
    fprintf(stderr, "fuzz: contract broken: %s (%s)\n", what, detail ? detail : "");
    abort();
}

static inline int fuzz_starts(const char *s, const char *prefix)
{
    return strncmp(s, prefix, strlen(prefix)) == 0;
}

#endif
