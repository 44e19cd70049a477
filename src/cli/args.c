/* args.c: see args.h. */
#include "cli/args.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/outfile.h"
#include "base/suggest.h"
#include "sim/rod.h"

static int is_help(const char *word)
{
    return strcmp(word, "--help") == 0 || strcmp(word, "-h") == 0;
}

/* An option word: '-' and more. A negative number ("--jobs -3") is a value,
 * so that its own check names what is accepted. */
static int is_option_word(const char *word)
{
    if (word[0] != '-' || word[1] == '\0') return 0;
    char *end;
    (void)strtod(word, &end);
    return end == word || *end != '\0';
}

/* The value's name in messages. */
static const char *noun_of(const cli_option *o)
{
    switch (o->value) {
    case CLI_SETTING: return "section.key=value";
    case CLI_FILE: return "a file name";
    case CLI_OUTPUT: return "a file name (or - for standard output)";
    case CLI_DIR: return "a directory";
    case CLI_COUNT: return "a whole number";
    default: return o->noun ? o->noun : "a value";
    }
}

/* The option `word` names (its name, its alias, or "--name=value" of a
 * value option), or NULL; *inline_value is the text after '=' then. */
static const cli_option *find_option(const cli_option *options, const char *word,
                                     const char **inline_value)
{
    *inline_value = NULL;
    for (const cli_option *o = options; o->name; o++)
        if (strcmp(word, o->name) == 0 || (o->alias && strcmp(word, o->alias) == 0)) return o;
    const char *eq = strchr(word, '=');
    if (!eq || strncmp(word, "--", 2) != 0) return NULL;
    size_t len = (size_t)(eq - word);
    for (const cli_option *o = options; o->name; o++)
        if (strlen(o->name) == len && strncmp(word, o->name, len) == 0) {
            *inline_value = eq + 1;
            return o;
        }
    return NULL;
}

/* "unknown option 'WORD'", and the nearest option's name when one is near
 * ("--cvs": did you mean --csv?). */
static void unknown_option(const cli_option *options, const char *word, char *err,
                           size_t errlen)
{
    enum { MAX_NAMES = 64 };
    const char *names[MAX_NAMES];
    int n = 0;
    for (const cli_option *o = options; o->name && n < MAX_NAMES - 1; o++) names[n++] = o->name;
    names[n] = NULL;
    char typed[64]; /* "--csv=x.csv" is compared as "--csv" */
    snprintf(typed, sizeof typed, "%.*s", (int)strcspn(word, "="), word);
    const char *near = suggest_nearest(typed, names);
    if (near) snprintf(err, errlen, "unknown option '%s'; did you mean %s?", word, near);
    else snprintf(err, errlen, "unknown option '%s'", word);
}

/* Checks a value by its option's kind. 0, or -1 with a message. */
static int check_value(const cli_option *o, const char *option, const char *value, char *err,
                       size_t errlen)
{
    if (value[0] == '\0') {
        snprintf(err, errlen, "%s needs %s, got an empty value", option, noun_of(o));
        return -1;
    }
    if (is_option_word(value)) {
        snprintf(err, errlen, "%s needs %s, got the option '%s'", option, noun_of(o), value);
        return -1;
    }
    if (strcmp(value, "-") == 0 && (o->value == CLI_FILE || o->value == CLI_DIR)) {
        snprintf(err, errlen, "%s needs %s, got '-' (standard output is not accepted here)",
                 option, noun_of(o));
        return -1;
    }
    if (o->value == CLI_SETTING && !strchr(value, '=')) {
        snprintf(err, errlen,
                 "%s expects section.key=value in one argument, got '%s' (write %s "
                 "%s=VALUE, no space around '=')",
                 option, value, option, value);
        return -1;
    }
    if (o->value == CLI_COUNT) {
        char *end;
        errno = 0;
        long n = strtol(value, &end, 10);
        if (end == value || *end != '\0' || errno || n < o->lo || n > o->hi) {
            snprintf(err, errlen, "%s %s: accepted: a whole number %ld .. %ld", option, value,
                     o->lo, o->hi);
            return -1;
        }
    }
    return 0;
}

/* Stores a checked value in the option's target. 0, or -1 out of memory. */
static int store(const cli_option *o, const char *value, int argc)
{
    if (o->value == CLI_FLAG || o->value == CLI_COUNT) {
        *(int *)o->target = o->value == CLI_FLAG ? 1 : (int)strtol(value, NULL, 10);
        return 0;
    }
    if (!o->repeated) {
        *(const char **)o->target = value;
        return 0;
    }
    cli_list *list = o->target;
    if (!list->items && !(list->items = calloc((size_t)argc, sizeof *list->items))) return -1;
    list->items[list->count++] = value;
    return 0;
}

/* A word that is not an option: the operand, once. */
static int take_operand(char **argv, int i, const cli_option *options,
                        const cli_operand *operand, char *err, size_t errlen)
{
    const char *word = argv[i];
    if (!operand || !operand->name) {
        snprintf(err, errlen, "unexpected argument '%s' (only options are accepted)", word);
        return -1;
    }
    if (!*operand->target) {
        *operand->target = word;
        return 0;
    }
    /* a value with spaces left unquoted: its second word comes here */
    const char *inline_value;
    const cli_option *before = i >= 2 ? find_option(options, argv[i - 2], &inline_value) : NULL;
    if (before && before->value == CLI_SETTING && !inline_value)
        snprintf(err, errlen, "'%s' follows %s %s: a value with spaces needs quotes "
                              "(--set tip.force=\"0 4e-7 0\"); only one %s may be given",
                 word, argv[i - 2], argv[i - 1], operand->name);
    else
        snprintf(err, errlen, "only one %s may be given ('%s' and '%s')", operand->name,
                 *operand->target, word);
    return -1;
}

int cli_parse(int argc, char **argv, const cli_option *options, const cli_operand *operand,
              char *err, size_t errlen)
{
    for (int i = 1; i < argc; i++)
        if (is_help(argv[i])) return CLI_HELP;
    for (int i = 1; i < argc; i++) {
        const char *word = argv[i];
        if (!is_option_word(word)) {
            if (take_operand(argv, i, options, operand, err, errlen)) return CLI_ERROR;
            continue;
        }
        const char *value;
        const cli_option *o = find_option(options, word, &value);
        if (!o) {
            unknown_option(options, word, err, errlen);
            return CLI_ERROR;
        }
        const char *option = value ? o->name : word; /* as typed: "-j" or "--jobs" */
        if (o->value == CLI_FLAG) {
            if (value) {
                snprintf(err, errlen, "%s takes no value ('%s')", option, word);
                return CLI_ERROR;
            }
        } else if (!value) {
            if (i + 1 >= argc) {
                snprintf(err, errlen, "%s needs %s", option, noun_of(o));
                return CLI_ERROR;
            }
            value = argv[++i];
        }
        if (o->value != CLI_FLAG && check_value(o, option, value, err, errlen)) return CLI_ERROR;
        if (store(o, value, argc)) {
            snprintf(err, errlen, "out of memory");
            return CLI_ERROR;
        }
    }
    if (operand && operand->name && !operand->optional && !*operand->target) {
        snprintf(err, errlen, "no %s given%s%s%s", operand->name, operand->hint ? " (" : "",
                 operand->hint ? operand->hint : "", operand->hint ? ")" : "");
        return CLI_ERROR;
    }
    return CLI_PARSED;
}

void cli_release(const cli_option *options)
{
    for (const cli_option *o = options; o->name; o++) {
        if (!o->repeated) continue;
        cli_list *list = o->target;
        free(list->items);
        list->items = NULL;
        list->count = 0;
    }
}

int cli_usage_error(const char *command, const char *message)
{
    fprintf(stderr, "rodsim %s: %s\n  (rodsim %s --help for the options)\n", command, message,
            command);
    return RUN_EXIT_BAD_INPUT;
}

void cli_unknown_name(char *err, size_t errlen, const char *option, const char *word,
                      const char *what, const char *const *names)
{
    const char *near = suggest_nearest(word, names);
    int len = snprintf(err, errlen, "%s '%s': unknown %s; %s%s%saccepted:", option, word, what,
                       near ? "did you mean " : "", near ? near : "", near ? "? " : "");
    for (int i = 0; names[i] && len >= 0 && (size_t)len < errlen; i++)
        len += snprintf(err + len, errlen - (size_t)len, "%s %s", i ? " |" : "", names[i]);
}

const char *const *cli_scheme_names(void)
{
    static const char *names[ROD_SCHEME_COUNT + 1];
    for (int k = 0; k < ROD_SCHEME_COUNT; k++) names[k] = rod_scheme_get((rod_scheme_kind)k)->name;
    names[ROD_SCHEME_COUNT] = NULL;
    return names;
}

int cli_check_output_file(const char *option, const char *path, char *err, size_t errlen)
{
    if (strcmp(path, "-") == 0) return 0;
    struct stat st;
    size_t n = strlen(path);
    if ((stat(path, &st) == 0 && S_ISDIR(st.st_mode)) || (n > 0 && path[n - 1] == '/')) {
        snprintf(err, errlen, "%s %s: names a directory, not a file", option, path);
        return -1;
    }
    /* a device, a pipe or a socket is written in place (outfile_reserve),
     * so it is the path itself that must be writable, not its folder */
    if (outfile_in_place(path)) {
        if (access(path, W_OK) == 0) return 0;
        snprintf(err, errlen, "%s %s: cannot write there: %s", option, path, strerror(errno));
        return -1;
    }
    char dir[OUTFILE_PATH_MAX], why[512];
    const char *slash = strrchr(path, '/');
    if (!slash) snprintf(dir, sizeof dir, ".");
    else if (slash == path) snprintf(dir, sizeof dir, "/");
    else snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    if (outfile_check_dir(dir, why, sizeof why)) {
        snprintf(err, errlen, "%s %s: %s", option, path, why);
        return -1;
    }
    return 0;
}
