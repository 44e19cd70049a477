/* test_deps.c: the Debian packages the Makefile can install are the ones
 * the README's table "Dependencies and why each is there" explains, each
 * under the target that needs it (DEBS_DEMO: `make demo`, DEBS_TEST:
 * `make test`), and tests/deps.sh, which installs them, behaves when it
 * cannot: with a fake `id` (not root), `sudo` and `apt-get` first in PATH,
 * it names each missing package on a line and exits 1, and a held package
 * manager lock is announced and waited for. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "test.h"

#define MAKEFILE RODSIM_SOURCE_DIR "/Makefile"
#define README RODSIM_SOURCE_DIR "/README.md"
#define DEPS_SH RODSIM_SOURCE_DIR "/tests/deps.sh"

#define MAX_PACKAGES 64

typedef struct package_list {
    int count;
    char name[MAX_PACKAGES][64];
    char target[MAX_PACKAGES][16]; /* "demo" or "test" */
} package_list;

static char *read_all(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = malloc((size_t)n + 1);
    if (text && fread(text, 1, (size_t)n, f) != (size_t)n) n = 0;
    if (text) text[n] = '\0';
    fclose(f);
    return text;
}

static void add(package_list *l, const char *name, size_t len, const char *target)
{
    if (l->count >= MAX_PACKAGES || len == 0 || len >= sizeof l->name[0]) return;
    memcpy(l->name[l->count], name, len);
    l->name[l->count][len] = '\0';
    snprintf(l->target[l->count], sizeof l->target[0], "%s", target);
    l->count++;
}

static int find(const package_list *l, const char *name)
{
    for (int i = 0; i < l->count; i++)
        if (strcmp(l->name[i], name) == 0) return i;
    return -1;
}

/* The words of the Makefile's `variable :=` line and its \-continuations. */
static void makefile_list(const char *makefile, const char *variable, const char *target,
                          package_list *l)
{
    char head[64];
    snprintf(head, sizeof head, "\n%s :=", variable);
    const char *p = strstr(makefile, head);
    if (!p) return;
    p += strlen(head);
    for (;;) {
        while (*p == ' ' || *p == '\t') p++;
        if (*p == '\\' && p[1] == '\n') {
            p += 2;
            continue;
        }
        if (*p == '\n' || *p == '\0') break;
        const char *start = p;
        while (*p && *p != ' ' && *p != '\t' && *p != '\n') p++;
        add(l, start, (size_t)(p - start), target);
    }
}

/* The README table's rows: `package`s in the first cell, `make TARGET` in the second. */
static void readme_list(const char *readme, package_list *l)
{
    const char *p = strstr(readme, "## Dependencies and why each is there");
    if (!p) return;
    const char *end = strstr(p + 3, "\n## ");
    for (p = strchr(p, '\n'); p && *p && (!end || p < end); p = strchr(p + 1, '\n')) {
        if (strncmp(p, "\n| `", 4) != 0) continue;
        const char *cell_end = strchr(p + 2, '|');
        const char *target_end = cell_end ? strchr(cell_end + 1, '|') : NULL;
        if (!target_end) continue;
        const char *target = strstr(cell_end, "`make ");
        char which[16] = "?";
        if (target && target < target_end) sscanf(target + 6, "%15[a-z]", which);
        for (const char *q = p + 2; q < cell_end; q++) {
            if (*q != '`') continue;
            const char *close = strchr(q + 1, '`');
            if (!close || close > cell_end) break;
            add(l, q + 1, (size_t)(close - q - 1), which);
            q = close;
        }
    }
}

static void test_lists(void)
{
    char *makefile = read_all(MAKEFILE), *readme = read_all(README);
    if (!check(makefile && readme, "read %s and %s", MAKEFILE, README)) return;
    package_list make = {0}, table = {0};
    makefile_list(makefile, "DEBS_DEMO", "demo", &make);
    makefile_list(makefile, "DEBS_TEST", "test", &make);
    readme_list(readme, &table);
    check(make.count >= 10, "Makefile's DEBS_DEMO and DEBS_TEST: %d packages", make.count);
    check(table.count >= 10, "README's dependency table: %d packages", table.count);
    for (int i = 0; i < make.count; i++) {
        int j = find(&table, make.name[i]);
        check(j >= 0 && strcmp(table.target[j], make.target[i]) == 0,
              "%s (Makefile: make %s) in the README's table under make %s", make.name[i],
              make.target[i], j >= 0 ? table.target[j] : "(absent)");
    }
    for (int j = 0; j < table.count; j++)
        check(find(&make, table.name[j]) >= 0,
              "%s (README's table) in the Makefile's DEBS_DEMO or DEBS_TEST", table.name[j]);
    free(makefile);
    free(readme);
}

/* Runs tests/deps.sh with fake id/sudo/apt-get first in PATH; output into log. */
static int run_deps(const char *dir, const char *apt_get, const char *packages, char *log,
                    size_t loglen)
{
    char command[2048];
    snprintf(command, sizeof command,
             "D='%s'; mkdir -p \"$D/bin\" && "
             "printf '#!/bin/sh\\necho 1000\\n' >\"$D/bin/id\" && "
             "printf '#!/bin/sh\\nexec \"$@\"\\n' >\"$D/bin/sudo\" && "
             "printf '#!/bin/sh\\n%s\\n' >\"$D/bin/apt-get\" && "
             "chmod +x \"$D/bin/id\" \"$D/bin/sudo\" \"$D/bin/apt-get\" && "
             "PATH=\"$D/bin:$PATH\" DEPS_LOCK_SECONDS=20 sh '%s' demo %s >\"$D/log\" 2>&1",
             dir, apt_get, DEPS_SH, packages);
    int status = system(command);
    char path[512];
    snprintf(path, sizeof path, "%s/log", dir);
    char *text = read_all(path);
    snprintf(log, loglen, "%s", text ? text : "");
    free(text);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static void test_script(void)
{
    char dir[] = "/tmp/rodsim_deps_XXXXXX";
    if (!check(mkdtemp(dir) != NULL, "scratch directory")) return;
    char log[4096];
    /* nothing missing: nothing run, even without root */
    int status = run_deps(dir, "exit 1", "", log, sizeof log);
    check(status == 0 && log[0] == '\0', "no package missing: exit %d (expected 0), output \"%s\"",
          status, log);
    /* apt-get fails: one line for each missing package, exit 1 */
    status = run_deps(dir, "exit 100", "rodsim-missing-one rodsim-missing-two", log, sizeof log);
    check(status == 1, "apt-get fails: exit %d (expected 1)", status);
    check(strstr(log, "missing Debian package rodsim-missing-one") &&
              strstr(log, "missing Debian package rodsim-missing-two"),
          "apt-get fails: each missing package named on a line: \"%s\"", log);
    /* a held lock: announced, waited for (the fake apt-get succeeds the second time) */
    char apt_get[512];
    snprintf(apt_get, sizeof apt_get,
             "if [ -e %s/tried ]; then exit 0; fi; touch %s/tried; "
             "echo \"E: Could not get lock /var/lib/dpkg/lock-frontend\"; exit 100",
             dir, dir);
    status = run_deps(dir, apt_get, "rodsim-missing-one", log, sizeof log);
    check(status == 0 && strstr(log, "waiting for the package manager lock"),
          "held lock: exit %d (expected 0), output \"%s\"", status, log);
    char clean[600];
    snprintf(clean, sizeof clean, "rm -rf '%s'", dir);
    if (system(clean) != 0) printf("note: %s failed\n", clean);
}

int main(void)
{
    test_lists();
    test_script();
    return test_finish();
}
