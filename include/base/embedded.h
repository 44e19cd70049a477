/* embedded.h: files of the source tree compiled into the binary (the
 * shaders, the scene `rodsim figure impulse` runs), so that an installed,
 * copied or moved binary needs nothing from the checkout it was built in.
 * The Makefile generates the table (build/<flavour>/gen/embedded.c) from
 * the files themselves: they stay the one source of truth, edited as files. */
#ifndef RODSIM_EMBEDDED_H
#define RODSIM_EMBEDDED_H

#include <stddef.h>

typedef struct embedded_file {
    const char *path;          /* as in the source tree: "shaders/scene.vert" */
    const unsigned char *data; /* the bytes, followed by a '\0' */
    size_t size;               /* bytes, without the '\0' */
} embedded_file;

/* Terminated by an entry whose path is NULL. Generated. */
extern const embedded_file embedded_files[];

/* The text of the embedded file at path ("scenes/impulse.ini"),
 * '\0'-terminated, static; NULL when no such file was embedded. */
const char *embedded_text(const char *path);

#endif
