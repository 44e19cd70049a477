/* textline.c: see textline.h. */
#include "base/textline.h"

#include <ctype.h>
#include <string.h>

int textline_next(FILE *f, const char *filename, char *line, size_t size, int *line_no,
                  char **text, char *err, size_t errlen)
{
    while (fgets(line, (int)size, f)) {
        ++*line_no;
        size_t n = strlen(line);
        /* a full buffer without its newline, before the end: the line goes on */
        if (n == size - 1 && line[n - 1] != '\n' && !feof(f)) {
            snprintf(err, errlen, "%s:%d: line longer than %zu characters", filename, *line_no,
                     size - 2);
            return -1;
        }
        char *hash = strchr(line, '#');
        if (hash) *hash = '\0';
        for (n = strlen(line); n > 0 && isspace((unsigned char)line[n - 1]); n--) line[n - 1] = '\0';
        char *start = line;
        while (isspace((unsigned char)*start)) start++;
        if (!*start) continue;
        *text = start;
        return 1;
    }
    return 0;
}
