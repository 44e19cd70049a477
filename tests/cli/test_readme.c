/* test_readme.c: the README is the program's own reference. Every generated
 * block (between "<!-- generated: rodsim ARGS -->" and "<!-- end generated
 * -->") equals what RODSIM_BIN prints for ARGS (tests/readme.sh check; `make
 * readme` rewrites them), in the README, docs/commands.md and docs/scene-keys.md;
 * the README is at most 30 KB and every
 * repository path it names exists. The exit statuses a signal gives (128 +
 * the signal: 130 SIGINT, 143 SIGTERM; every command but live takes them
 * through outfile's cleanup handler) are in `rodsim help` as the README
 * shows it, in docs/commands.md's sentence on every command's exit status
 * and in the prose of docs/commands.md's run section. */
#include <signal.h>
#include <ctype.h>
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "test.h"

#define README RODSIM_SOURCE_DIR "/README.md"
/* the scene reference, beside the scenes (it would not fit in 30 KB) */
#define SCENES_README RODSIM_SOURCE_DIR "/scenes/README.md"
/* every scene key: the program's own tables, beside the decision records */
#define SCENE_KEYS_DOC RODSIM_SOURCE_DIR "/docs/scene-keys.md"
/* every command's --help, beside the decision records */
#define COMMANDS_DOC RODSIM_SOURCE_DIR "/docs/commands.md"

static void test_generated_blocks(const char *readme, int want)
{
    char command[2048];
    snprintf(command, sizeof command, "sh '%s/tests/readme.sh' check '%s' '%s' 2>&1 >/dev/null",
             RODSIM_SOURCE_DIR, RODSIM_BIN, readme);
    fflush(stdout);
    FILE *p = popen(command, "r");
    if (!check(p != NULL, "tests/readme.sh check runs")) return;
    char line[4096];
    int same = 0, differ = 0;
    while (fgets(line, sizeof line, p)) {
        line[strcspn(line, "\n")] = '\0';
        if (strncmp(line, "same: ", 6) == 0) {
            same++;
            check(1, "README block '%s' is the program's output", line + 6);
        } else if (strncmp(line, "differs: ", 9) == 0) {
            differ++;
            check(0, "README block %s", line + 9);
        }
    }
    int status = pclose(p);
    check(status == 0 && differ == 0 && same >= want,
          "every generated block of %s equals the program's output: %d same, %d differ "
          "(want >= %d and 0), status %d", readme, same, differ, want, status);
}

/* Every command `rodsim help` lists (its lines "  NAME   summary" between
 * "commands:" and the blank line) has its --help block in docs/commands.md,
 * which says it holds every command and option. */
static void test_every_command_documented(void)
{
    char command[1024];
    snprintf(command, sizeof command, "'%s' help", RODSIM_BIN);
    fflush(stdout);
    FILE *p = popen(command, "r");
    if (!check(p != NULL, "rodsim help runs")) return;
    FILE *doc = fopen(COMMANDS_DOC, "rb");
    static char text[200000]; /* docs/commands.md: about 30 KB */
    size_t got = doc ? fread(text, 1, sizeof text - 1, doc) : 0;
    text[got] = '\0';
    if (doc) fclose(doc);
    char line[512];
    int listing = 0, commands = 0, missing = 0;
    while (fgets(line, sizeof line, p)) {
        if (strncmp(line, "commands:", 9) == 0) {
            listing = 1;
            continue;
        }
        if (!listing) continue;
        char name[64];
        if (line[0] == '\n' || sscanf(line, " %63s", name) != 1) break;
        char block[160];
        snprintf(block, sizeof block, "<!-- generated: rodsim %s --help -->", name);
        commands++;
        if (!strstr(text, block)) {
            missing++;
            check(0, "docs/commands.md has no block '%s'", block);
        }
    }
    pclose(p);
    check(commands >= 9 && missing == 0,
          "docs/commands.md holds the --help of every command rodsim help lists: %d "
          "commands, %d without a block", commands, missing);
}

/* Every shipped scene (each .ini file in scenes/) is named in scenes/README.md's guide,
 * which lists what each shows. */
static void test_every_scene_listed(const char *guide)
{
    DIR *d = opendir(RODSIM_SOURCE_DIR "/scenes");
    if (!check(d != NULL, "scenes/ opens")) return;
    int scenes = 0, missing = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        size_t n = strlen(e->d_name);
        if (n < 5 || strcmp(e->d_name + n - 4, ".ini") != 0) continue;
        char named[300];
        snprintf(named, sizeof named, "`%s`", e->d_name);
        scenes++;
        if (!strstr(guide, named)) {
            missing++;
            check(0, "scenes/README.md does not name %s", named);
        }
    }
    closedir(d);
    check(scenes > 10 && missing == 0, "scenes/README.md names every scene: %d scenes, %d not "
          "named", scenes, missing);
}

/* Whether the text from `start` to the next `end` after it names 128 +
 * SIGINT and 128 + SIGTERM. */
static void check_signal_statuses(const char *text, const char *start, const char *end,
                                  const char *what)
{
    const char *from = text ? strstr(text, start) : NULL;
    const char *to = from ? strstr(from, end) : NULL;
    char want_int[8], want_term[8];
    snprintf(want_int, sizeof want_int, "%d", 128 + SIGINT);
    snprintf(want_term, sizeof want_term, "%d", 128 + SIGTERM);
    const char *said_int = from ? strstr(from, want_int) : NULL;
    const char *said_term = from ? strstr(from, want_term) : NULL;
    int ok = from && to && said_int && said_int < to && said_term && said_term < to;
    check(ok, "%s names the exit statuses %s (SIGINT) and %s (SIGTERM): %s", what, want_int,
          want_term, ok ? "yes" : "no");
}

static char *read_readme(const char *path, long *size)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    *size = ftell(f);
    rewind(f);
    char *text = malloc((size_t)*size + 1);
    if (text && fread(text, 1, (size_t)*size, f) != (size_t)*size) {
        free(text);
        text = NULL;
    }
    if (text) text[*size] = '\0';
    fclose(f);
    return text;
}

/* Every word that starts with a source folder ("src/sim/rod.c", "scenes/x.ini")
 * names a file or folder of the repository. Words with capitals are
 * placeholders ("tests/LAYER/test_NAME.c") and are skipped. */
static void test_paths_exist(const char *text)
{
    static const char *const roots[] = {"src/", "include/", "tests/", "scenes/", "shaders/", NULL};
    int named = 0, missing = 0;
    for (const char *p = text; *p; p++) {
        if (p > text && (isalnum((unsigned char)p[-1]) || p[-1] == '/' || p[-1] == '_' ||
                         p[-1] == '.' || p[-1] == '-'))
            continue;
        for (int r = 0; roots[r]; r++) {
            size_t n = strlen(roots[r]);
            if (strncmp(p, roots[r], n) != 0) continue;
            size_t len = n;
            while (isalnum((unsigned char)p[len]) || strchr("_./-", p[len])) len++;
            while (len > n && strchr(".,:-", p[len - 1])) len--;
            char word[256];
            snprintf(word, sizeof word, "%.*s", (int)len, p);
            int placeholder = 0;
            for (const char *c = word; *c; c++)
                if (isupper((unsigned char)*c)) placeholder = 1;
            if (placeholder || strchr(word, '*')) break;
            char path[512];
            snprintf(path, sizeof path, "%s/%s", RODSIM_SOURCE_DIR, word);
            named++;
            if (access(path, F_OK) != 0) {
                missing++;
                check(0, "README names %s, which is not in the repository", word);
            }
            break;
        }
    }
    check(named > 10 && missing == 0, "README names %d repository paths, %d missing", named,
          missing);
    check(!strstr(text, "](out/"), "README shows no image from out/ (not committed)");
    check(!strstr(text, "PRODUCT.md") && !strstr(text, "reference/"),
          "README names no file outside the repository (PRODUCT.md, reference/)");
}

int main(void)
{
    test_generated_blocks(README, 1);        /* help */
    test_generated_blocks(COMMANDS_DOC, 9);  /* every command's --help */
    test_every_command_documented();
    test_generated_blocks(SCENE_KEYS_DOC, 2); /* help scene, help beam */
    long size = 0;
    char *text = read_readme(README, &size);
    if (check(text != NULL, "README.md reads")) {
        check(size <= 30 * 1024, "README.md is %ld bytes, at most 30 KB (%d)", size, 30 * 1024);
        test_paths_exist(text);
        check_signal_statuses(text, "<!-- generated: rodsim help -->", "<!-- end generated -->",
                              "README's rodsim help (every command's exit status)");
    }
    free(text);
    /* docs/commands.md's run section: its prose after the generated --help,
     * before its subsections (the summary's says a stopped run has none) */
    text = read_readme(COMMANDS_DOC, &size);
    const char *run = text ? strstr(text, "<!-- generated: rodsim run --help -->") : NULL;
    const char *prose = run ? strstr(run, "<!-- end generated -->") : NULL;
    check_signal_statuses(prose, "<!-- end generated -->", "\n### ",
                          "docs/commands.md's run section (its prose)");
    check_signal_statuses(text, "Exit status of every command", "\n\n",
                          "docs/commands.md's exit status of every command");
    free(text);
    /* the scenes' guide too: the key tables stand in docs/scene-keys.md */
    text = read_readme(SCENES_README, &size);
    if (check(text != NULL, "scenes/README.md reads")) {
        check(size <= 30 * 1024, "scenes/README.md is %ld bytes, at most 30 KB (%d)", size,
              30 * 1024);
        test_every_scene_listed(text);
    }
    free(text);
    return test_finish();
}
