/* textline.c: see textline.h. */
#include "base/textline.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/textfile.h"

int textline_next(const char **cursor, const char *filename, char *line, size_t size,
                  int *line_no, char **text, char *err, size_t errlen)
{
    const char *p = *cursor;
    if (*line_no == 0) p = textfile_skip_bom(p);
    while (*p) {
        ++*line_no;
        const char *begin = p, *eol = strchr(p, '\n');
        size_t n = eol ? (size_t)(eol - begin) : strlen(begin);
        *cursor = p = eol ? eol + 1 : begin + n;
        if (n > size - 2) {
            snprintf(err, errlen, "%s:%d: line longer than %zu characters", filename, *line_no,
                     size - 2);
            return -1;
        }
        memcpy(line, begin, n);
        line[n] = '\0';
        char *hash = strchr(line, '#');
        if (hash) *hash = '\0';
        for (n = strlen(line); n > 0 && isspace((unsigned char)line[n - 1]); n--) line[n - 1] = '\0';
        char *start = line;
        while (isspace((unsigned char)*start)) start++;
        if (!*start) continue;
        *text = start;
        return 1;
    }
    *cursor = p;
    return 0;
}

int textline_numbers(char *line, double *values, int max)
{
    int count = 0;
    char *p = line;
    for (;;) {
        while (*p == ' ' || *p == '\t') p++;
        if (!*p) break;
        char *b = p;
        while (*p && *p != ',') p++;
        char *e = p;
        while (e > b && isspace((unsigned char)e[-1])) e--;
        if (count == max || e == b) return -1;
        char keep = *e;
        *e = '\0';
        char *stop;
        errno = 0;
        double v = strtod(b, &stop);
        int ok = stop == e && errno != ERANGE && isfinite(v);
        *e = keep;
        if (!ok) return -1;
        values[count++] = v;
        if (*p == ',') {
            p++;
            if (!*p) return -1; /* trailing comma: an empty field */
        }
    }
    return count;
}
