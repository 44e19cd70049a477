/* print_commands.h: what `--print-commands` (validate, figure) needs so that
 * every printed line runs as printed, from any directory, with any PATH (GNU
 * parallel, a Slurm array): the binary's absolute path, absolute file names,
 * and words quoted for /bin/sh. */
#ifndef RODSIM_PRINT_COMMANDS_H
#define RODSIM_PRINT_COMMANDS_H

#include <stddef.h>
#include <stdio.h>

/* The running binary's absolute, symlink-free path (realpath of
 * /proc/self/exe). 0, or -1 with a message in err. */
int cli_self_path(char *out, size_t outlen, char *err, size_t errlen);

/* `path` made absolute against the current directory (it need not exist;
 * "." and ".." are kept: the shell resolves them the same). 0, or -1 with a
 * message in err. */
int cli_absolute_path(const char *path, char *out, size_t outlen, char *err, size_t errlen);

/* Writes `word` to f so that /bin/sh reads it back as one word: as is when it
 * holds only safe characters, else in single quotes ('\'' for a quote). */
void cli_print_shell_word(FILE *f, const char *word);

#endif
