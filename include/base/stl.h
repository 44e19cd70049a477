/* stl.h: triangle meshes read from STL files (ASCII or binary), bounded.
 *
 * The reader takes the whole file into memory and parses it there (so a
 * fuzzer can feed it bytes). A binary file is told from an ASCII one by its
 * size: 84 + 50 n bytes for the n triangles its header counts; anything else
 * that starts with "solid" is read as ASCII. The facet normals in the file
 * are ignored: a triangle's outward side is the one its vertices turn
 * counter-clockwise about (the right-hand rule), as the format specifies.
 * Messages start with the file's name and say where: "FILE:LINE: ..." for
 * ASCII, "FILE: byte N: ..." for binary.
 */
#ifndef RODSIM_BASE_STL_H
#define RODSIM_BASE_STL_H

#include <stddef.h>

/* The most bytes an STL file may hold (a binary file of 5 million triangles). */
#define STL_MAX_BYTES ((size_t)256 << 20)

typedef struct stl_mesh {
    int triangle_count;
    double *triangles;  /* (triangle_count x 9): vertices a b c, x y z each, in the
                           file's units; malloc'd, freed by stl_release */
    int dropped;        /* degenerate triangles (zero area) left out */
} stl_mesh;

/* Parses `size` bytes of an STL file named `name` (for messages) into out.
 * At most max_triangles triangles are accepted: a file that holds more is
 * refused before any is read, the message naming `limit_key` (the setting
 * that raises the limit). Degenerate triangles (area below 1e-12 of the
 * square of their longest edge) are dropped and counted, the first one's
 * place written to warn (may be NULL) as "FILE:LINE: ..." or "FILE: byte N:
 * ..."; a NaN or infinite coordinate is refused, as is a file with no
 * triangle left. Returns 0, or -1 with a message in err. */
int stl_parse(const char *name, const unsigned char *data, size_t size, int max_triangles,
              const char *limit_key, stl_mesh *out, char *warn, size_t warnlen, char *err,
              size_t errlen);

/* Reads the file at `path` (a regular file of at most STL_MAX_BYTES) and
 * parses it (stl_parse). */
int stl_load(const char *path, int max_triangles, const char *limit_key, stl_mesh *out,
             char *warn, size_t warnlen, char *err, size_t errlen);

/* Frees out's triangles; out may be zeroed or already released. */
void stl_release(stl_mesh *out);

#endif
