/* args.c: see args.h. */
#include "cli/args.h"

#include <stdio.h>
#include <string.h>

int cli_option_value(const char *option, const char *value, char *err, size_t errlen)
{
    if (value[0] == '\0') {
        snprintf(err, errlen, "%s needs a value, got an empty one", option);
        return -1;
    }
    if (value[0] == '-' && value[1] != '\0') {
        snprintf(err, errlen, "%s needs %s, got the option '%s'", option,
                 strcmp(option, "--set") == 0 ? "section.key=value"
                 : strcmp(option, "-o") == 0  ? "a directory"
                                              : "a file name (or - for standard output)",
                 value);
        return -1;
    }
    if (strcmp(option, "--set") == 0 && !strchr(value, '=')) {
        snprintf(err, errlen,
                 "--set expects section.key=value in one argument, got '%s' (write --set "
                 "%s=VALUE, no space around '=')",
                 value, value);
        return -1;
    }
    return 0;
}
