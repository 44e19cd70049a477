/* print_commands.c: absolute paths and shell quoting (see print_commands.h). */
#include "cli/print_commands.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int cli_self_path(char *out, size_t outlen, char *err, size_t errlen)
{
    char resolved[PATH_MAX];
    if (!realpath("/proc/self/exe", resolved)) {
        snprintf(err, errlen, "cannot find this program's own path (/proc/self/exe): %s",
                 strerror(errno));
        return -1;
    }
    if (snprintf(out, outlen, "%s", resolved) >= (int)outlen) {
        snprintf(err, errlen, "this program's path is too long: %s", resolved);
        return -1;
    }
    return 0;
}

int cli_absolute_path(const char *path, char *out, size_t outlen, char *err, size_t errlen)
{
    if (path[0] == '/') {
        if (snprintf(out, outlen, "%s", path) < (int)outlen) return 0;
        snprintf(err, errlen, "%s: path too long", path);
        return -1;
    }
    char cwd[PATH_MAX];
    if (!getcwd(cwd, sizeof cwd)) {
        snprintf(err, errlen, "cannot read the current directory: %s", strerror(errno));
        return -1;
    }
    const char *rest = strncmp(path, "./", 2) == 0 ? path + 2 : path;
    if (snprintf(out, outlen, "%s/%s", cwd, rest) >= (int)outlen) {
        snprintf(err, errlen, "%s/%s: path too long", cwd, rest);
        return -1;
    }
    return 0;
}

void cli_print_shell_word(FILE *f, const char *word)
{
    static const char safe[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                               "0123456789_./-+=,:@%";
    if (word[0] != '\0' && word[strspn(word, safe)] == '\0') {
        fputs(word, f);
        return;
    }
    fputc('\'', f);
    for (const char *c = word; *c; c++) {
        if (*c == '\'') fputs("'\\''", f);
        else fputc(*c, f);
    }
    fputc('\'', f);
}
