/* textline.h: the lines of a small text table (load tables, paths, shapes)
 * held in memory (textfile_read): '#' comments and surrounding blanks
 * removed, blank lines skipped, a line too long for the buffer refused (not
 * read as two rows). */
#ifndef RODSIM_TEXTLINE_H
#define RODSIM_TEXTLINE_H

#include <stddef.h>

/* Copies the next non-blank line of the text at *cursor (NUL-terminated; the
 * cursor moves past the line) into line (size bytes), counting lines in
 * *line_no (start it at 0: a UTF-8 byte-order mark before the first line is
 * skipped). Returns 1 with *text pointing at the trimmed text inside line, 0
 * at the end of the text, or -1 with "FILENAME:LINE: line longer than N
 * characters" in err (N = size - 2, the newline not counted). */
int textline_next(const char **cursor, const char *filename, char *line, size_t size,
                  int *line_no, char **text, char *err, size_t errlen);

/* Splits a data line at commas into at most `max` finite numbers (blanks
 * around each allowed); returns the count, or -1 at an empty, non-numeric,
 * out-of-range or non-finite field, or more than `max` fields. The line is
 * restored as it was. */
int textline_numbers(char *line, double *values, int max);

#endif
