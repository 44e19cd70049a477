/* args.h: what the subcommands' option parsers share. */
#ifndef RODSIM_ARGS_H
#define RODSIM_ARGS_H

#include <stddef.h>

/* Checks the value of an option that takes one: an option word is not a
 * value (`--csv -o` forgot the file name), except "-" (standard output) for
 * options that write a file; `--set` needs section.key=value in one
 * argument. 0, or -1 with a message naming the option and what it needs. */
int cli_option_value(const char *option, const char *value, char *err, size_t errlen);

#endif
