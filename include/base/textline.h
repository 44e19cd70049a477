/* textline.h: the lines of a small text table (load tables, paths, shapes):
 * '#' comments and surrounding blanks removed, blank lines skipped, a line
 * too long for the buffer refused (not read as two rows). */
#ifndef RODSIM_TEXTLINE_H
#define RODSIM_TEXTLINE_H

#include <stddef.h>
#include <stdio.h>

/* Reads the next non-blank line of f into line (size bytes), counting lines
 * in *line_no (start it at 0). Returns 1 with *text pointing at the trimmed
 * text inside line, 0 at the end of the file, or -1 with
 * "FILENAME:LINE: line longer than N characters" in err. */
int textline_next(FILE *f, const char *filename, char *line, size_t size, int *line_no,
                  char **text, char *err, size_t errlen);

#endif
