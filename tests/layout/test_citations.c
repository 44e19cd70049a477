/* test_citations.c: the docs' citations of code name what is there.
 *
 * A citation is a code span `DIR/FILE.c: NAME` or `DIR/FILE.h:NAME` (DIR:
 * src, include or tests; the space after the colon optional) in README.md,
 * scenes/README.md and the .md files of docs/ and docs/decisions/: the file
 * must exist and hold NAME as a whole word. CHANGELOG.md is left out: it
 * tells what changed when, in the names of the time.
 *
 * The checker runs first on synthetic text (a citation of a missing file
 * and of a missing name must be caught, a true one must pass), then on the
 * tree at RODSIM_SOURCE_DIR. */
#include <ctype.h>
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test.h"

#define PATH_LEN 1024

static char *read_whole(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 4096, len = 0;
    char *text = malloc(cap);
    size_t got;
    while (text && (got = fread(text + len, 1, cap - len - 1, f)) > 0) {
        len += got;
        if (len + 1 == cap) {
            char *more = realloc(text, cap * 2);
            if (!more) {
                free(text);
                text = NULL;
                break;
            }
            text = more;
            cap *= 2;
        }
    }
    fclose(f);
    if (text) text[len] = '\0';
    return text;
}

static int word_char(int c)
{
    return isalnum(c) || c == '_';
}

/* 1 when text holds name as a whole word */
static int has_word(const char *text, const char *name)
{
    const size_t n = strlen(name);
    for (const char *p = strstr(text, name); p; p = strstr(p + 1, name))
        if ((p == text || !word_char((unsigned char)p[-1])) && !word_char((unsigned char)p[n]))
            return 1;
    return 0;
}

/* The citation in the code span [span, end) as its file and name: 1, else
 * 0 (not a citation) */
static int parse_citation(const char *span, const char *end, char *file, size_t file_len,
                          char *name, size_t name_len)
{
    static const char *const dirs[] = {"src/", "include/", "tests/"};
    int under = 0;
    for (int d = 0; d < 3; d++) under |= strncmp(span, dirs[d], strlen(dirs[d])) == 0;
    if (!under) return 0;
    const char *colon = memchr(span, ':', (size_t)(end - span));
    if (!colon || colon - span < 3 || colon[-2] != '.' || (colon[-1] != 'c' && colon[-1] != 'h'))
        return 0;
    for (const char *p = span; p < colon; p++)
        if (!(word_char((unsigned char)*p) || *p == '/' || *p == '.' || *p == '-')) return 0;
    const char *n = colon + 1;
    if (n < end && *n == ' ') n++;
    if (n == end) return 0;
    for (const char *p = n; p < end; p++)
        if (!word_char((unsigned char)*p)) return 0;
    if ((size_t)(colon - span) >= file_len || (size_t)(end - n) >= name_len) return 0;
    snprintf(file, file_len, "%.*s", (int)(colon - span), span);
    snprintf(name, name_len, "%.*s", (int)(end - n), n);
    return 1;
}

/* Checks every citation of the document `doc` (its text) against the tree
 * at root; the first broken one into last. Returns the count of citations
 * seen; *broken counts those that name a missing file or a name the file
 * does not hold. print: a FAIL line each (the real tree). */
static int check_doc(const char *root, const char *doc, const char *text, int *broken,
                     char *last, size_t last_len, int print)
{
    int seen = 0;
    for (const char *p = strchr(text, '`'); p; p = strchr(p + 1, '`')) {
        const char *end = strchr(p + 1, '`');
        if (!end) break;
        char file[PATH_LEN], name[256];
        if (parse_citation(p + 1, end, file, sizeof file, name, sizeof name)) {
            seen++;
            char path[2 * PATH_LEN];
            snprintf(path, sizeof path, "%s/%s", root, file);
            char *code = read_whole(path);
            if (!code || !has_word(code, name)) {
                ++*broken;
                snprintf(last, last_len, "%s: `%s: %s`: %s", doc, file, name,
                         code ? "the file does not hold the name" : "no such file");
                if (print) check(0, "%s", last);
            }
            free(code);
        }
        p = end;
    }
    return seen;
}

static void test_synthetic(void)
{
    char last[PATH_LEN + 512] = "";
    int broken = 0;
    const char *root = RODSIM_SOURCE_DIR;
    int seen = check_doc(root, "synthetic", "a true one (`src/cli/live_step.c: live_line_budget`)",
                         &broken, last, sizeof last, 0);
    check(seen == 1 && broken == 0, "a true citation passes (%d seen, %d broken)", seen, broken);
    broken = 0;
    seen = check_doc(root, "synthetic", "`src/cli/live.c: line_budget`", &broken, last,
                     sizeof last, 0);
    check(seen == 1 && broken == 1 && strstr(last, "does not hold"),
          "a name the file does not hold is caught: %s", last);
    broken = 0;
    seen = check_doc(root, "synthetic", "`src/cli/no_such_file.c:live_line_budget`", &broken,
                     last, sizeof last, 0);
    check(seen == 1 && broken == 1 && strstr(last, "no such file"),
          "a file that does not exist is caught: %s", last);
    broken = 0;
    seen = check_doc(root, "synthetic", "`live_step.c` and `src/cli/live_step.c` and "
                     "`rod.friction: 0.5` and `src/x.c: a b`", &broken, last, sizeof last, 0);
    check(seen == 0 && broken == 0, "spans that are no citation are passed over (%d seen)", seen);
    broken = 0;
    seen = check_doc(root, "synthetic", "`src/sim/rod.c:rod_choose_dt`", &broken, last,
                     sizeof last, 0);
    check(seen == 1 && broken == 0, "a citation without the space passes (%d seen, %d broken)",
          seen, broken);
}

/* Checks the documents of folder `dir` (from the root) ending in .md */
static void check_folder(const char *root, const char *dir, int *seen, int *broken, char *last,
                         size_t last_len)
{
    char path[4 * PATH_LEN];
    snprintf(path, sizeof path, "%s/%s", root, dir);
    DIR *d = opendir(path);
    if (!check(d != NULL, "%s opened", dir)) return;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        const size_t n = strlen(e->d_name);
        if (n < 4 || strcmp(e->d_name + n - 3, ".md") != 0) continue;
        char doc[PATH_LEN + 300];
        snprintf(doc, sizeof doc, "%s/%s", dir, e->d_name);
        snprintf(path, sizeof path, "%s/%s", root, doc);
        char *text = read_whole(path);
        if (text) *seen += check_doc(root, doc, text, broken, last, last_len, 1);
        free(text);
    }
    closedir(d);
}

static void test_tree(void)
{
    const char *root = RODSIM_SOURCE_DIR;
    char last[PATH_LEN + 512] = "";
    int seen = 0, broken = 0;
    static const char *const docs[] = {"README.md", "scenes/README.md"};
    for (int k = 0; k < 2; k++) {
        char path[2 * PATH_LEN];
        snprintf(path, sizeof path, "%s/%s", root, docs[k]);
        char *text = read_whole(path);
        if (check(text != NULL, "%s read", docs[k]))
            seen += check_doc(root, docs[k], text, &broken, last, sizeof last, 1);
        free(text);
    }
    check_folder(root, "docs", &seen, &broken, last, sizeof last);
    check_folder(root, "docs/decisions", &seen, &broken, last, sizeof last);
    check(seen > 0 && broken == 0, "the docs' %d citations of code name what is there (%d broken)",
          seen, broken);
}

int main(void)
{
    test_synthetic();
    test_tree();
    return test_finish();
}
