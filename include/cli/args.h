/* args.h: what every subcommand shares: its exit statuses and the one
 * option parser. Every subcommand reads its words through cli_parse, so an
 * unknown option, a missing value or a second SCENE gets the same message
 * everywhere, and cli_usage_error the same exit status, 2. */
#ifndef RODSIM_ARGS_H
#define RODSIM_ARGS_H

#include <stddef.h>

/* Exit statuses of every command. */
enum {
    RUN_EXIT_OK = 0,
    RUN_EXIT_FAILURE = 1,  /* out of memory, a file that cannot be written, ... */
    RUN_EXIT_BAD_INPUT = 2 /* bad scene or usage, or a numerically unstable run */
};

/* What an option takes, which also says how its value is checked. */
typedef enum cli_value {
    CLI_FLAG,    /* no value: the int target is set to 1 */
    CLI_WORD,    /* any word that is not an option (the command checks it) */
    CLI_SETTING, /* section.key=value, in one word */
    CLI_FILE,    /* a file name ("-" refused) */
    CLI_OUTPUT,  /* a file name, or "-" for standard output */
    CLI_DIR,     /* a directory ("-" refused) */
    CLI_COUNT    /* a whole number in lo .. hi; the target is an int */
} cli_value;

/* The values of a repeated option, in the order given. items is allocated
 * by cli_parse (argc entries) and points into argv; cli_release frees it. */
typedef struct cli_list {
    const char **items;
    int count;
} cli_list;

/* One row of a subcommand's option table; a row with name NULL ends it. */
typedef struct cli_option {
    const char *name;  /* "--csv"; a value option also takes "--csv=FILE" */
    const char *alias; /* another spelling ("-o", "-q", "-j"), or NULL */
    cli_value value;
    void *target;      /* int * (CLI_FLAG, CLI_COUNT), const char ** (the last one
                        * given wins), or cli_list * when repeated */
    int repeated;
    long lo, hi;       /* CLI_COUNT's accepted range */
    const char *noun;  /* CLI_WORD: what the value is, for messages ("a scheme");
                        * NULL: "a value" */
} cli_option;

/* The one word that is not an option (SCENE, RECORD, NAME), if any. */
typedef struct cli_operand {
    const char *name;    /* "SCENE"; NULL: the command takes none */
    const char *hint;    /* added to "no SCENE given", or NULL */
    int optional;        /* 1: it may be left out */
    const char **target; /* NULL until given */
} cli_operand;

/* cli_parse's answers. */
enum { CLI_PARSED = 0, CLI_HELP = 1, CLI_ERROR = -1 };

/* Reads argv[1 .. argc-1] (argv[0] is the command's name) into the targets
 * of `options` and `operand` (may be NULL: no operand). --help or -h
 * anywhere answers CLI_HELP before anything else is read. Otherwise
 * CLI_PARSED, or CLI_ERROR with one message in err: an unknown option, a
 * value missing, empty, an option word or refused by its kind, a count out
 * of range, a second operand, or a required operand missing. */
int cli_parse(int argc, char **argv, const cli_option *options, const cli_operand *operand,
              char *err, size_t errlen);

/* Frees what cli_parse allocated for the table's repeated options (their
 * cli_list items); the lists are left empty. */
void cli_release(const cli_option *options);

/* A word that is none of `names` (NULL-terminated): "OPTION 'WORD': unknown
 * WHAT; did you mean NAME? accepted: A | B | ..." into err, the suggestion
 * only when a name is near (suggest.h). */
void cli_unknown_name(char *err, size_t errlen, const char *option, const char *word,
                      const char *what, const char *const *names);

/* An output file named by `option` (--csv FILE), checked before any work:
 * not a directory, in a directory that is or can be made. "-" (standard
 * output) passes. 0, or -1 with "OPTION FILE: why" in err. */
int cli_check_output_file(const char *option, const char *path, char *err, size_t errlen);

/* The schemes' names (thesis, implicit, static), NULL-terminated. */
const char *const *cli_scheme_names(void);

/* Prints "rodsim COMMAND: MESSAGE" and where the options are listed to
 * stderr. Returns RUN_EXIT_BAD_INPUT, the status of every usage error. */
int cli_usage_error(const char *command, const char *message);

#endif
