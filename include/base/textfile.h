/* textfile.h: a whole text file read into memory, with a bound on what is read.
 *
 * The one reader of the files rodsim is given as input (scenes, shapes, paths,
 * load tables): each caller states the most bytes it accepts, and nothing is
 * read past that bound. A device is refused before any byte is read (/dev/zero
 * never ends, a terminal waits), a directory too; a pipe (a FIFO, `<(...)`) is
 * read, up to limit + 1 bytes at most. The text is then parsed from memory, so
 * a parser can be fuzzed without files.
 */
#ifndef RODSIM_TEXTFILE_H
#define RODSIM_TEXTFILE_H

#include <stddef.h>

/* Reads the file at `path` into *text (NUL-terminated, malloc'd: the caller
 * frees it), its length in bytes in *length (may be NULL). `what` names the
 * file's role in messages ("scene", "load table": "the WHAT file"); `limit` is the most
 * bytes accepted. Returns 0, or -1 with *text NULL and a message in err that
 * starts with the path and names the limit: the file cannot be opened; it is
 * a directory, a device or a socket; it holds more than `limit` bytes; it is
 * UTF-16 text; it holds a NUL byte (text only). A leading UTF-8 byte-order
 * mark is kept in the text: parsers skip it (textfile_skip_bom). */
int textfile_read(const char *path, const char *what, size_t limit, char **text, size_t *length,
                  char *err, size_t errlen);

/* `text` past a leading UTF-8 byte-order mark (EF BB BF), which some editors
 * write at the start of a file; `text` itself when there is none. */
const char *textfile_skip_bom(const char *text);

#endif
