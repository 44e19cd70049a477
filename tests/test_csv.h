/* test_csv.h: reading the CSV files the sweep and run tests check: a whole
 * file as text, a cell by row and column, a column by its header name.
 * Fields may be RFC 4180 quoted (a knot's name "trefoil, right-handed"
 * holds a comma); these files have no doubled quotes inside a field. */
#ifndef RODSIM_TEST_CSV_H
#define RODSIM_TEST_CSV_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The file at path as a string (the caller frees it), NULL when it cannot
 * be read */
static inline char *read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    const long n = ftell(f);
    rewind(f);
    char *text = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (text) text[fread(text, 1, (size_t)n, f)] = '\0';
    fclose(f);
    return text;
}

/* The end of the field that starts at p (its comma, newline or NUL) */
static inline const char *csv_field_end(const char *p)
{
    int quoted = 0;
    for (; *p && (quoted || (*p != ',' && *p != '\n')); p++)
        if (*p == '"') quoted = !quoted;
    return p;
}

/* Field `column` (0-based) of CSV line `row` (0: the header) of text into
 * out, its quotes taken off; 0, or -1 when there is no such field */
static inline int csv_cell(const char *text, int row, int column, char *out, size_t n)
{
    const char *p = text;
    for (int r = 0; r < row && p; r++) {
        p = strchr(p, '\n');
        if (p) p++;
    }
    for (int c = 0; c < column && p; c++) {
        p = csv_field_end(p);
        p = *p == ',' ? p + 1 : NULL;
    }
    if (!p) return -1;
    size_t len = (size_t)(csv_field_end(p) - p);
    if (len >= 2 && p[0] == '"' && p[len - 1] == '"') {
        p++;
        len -= 2;
    }
    snprintf(out, n, "%.*s", (int)len, p);
    return 0;
}

/* The column named `name` in the header of text; -1 when none */
static inline int csv_column(const char *text, const char *name)
{
    char cell[128];
    for (int c = 0; c < 64 && csv_cell(text, 0, c, cell, sizeof cell) == 0; c++)
        if (strcmp(cell, name) == 0) return c;
    return -1;
}

#endif
