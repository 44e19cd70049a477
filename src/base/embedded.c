/* embedded.c: looking up the files the Makefile compiled in (see embedded.h). */
#include "base/embedded.h"

#include <string.h>

const char *embedded_text(const char *path)
{
    for (const embedded_file *f = embedded_files; f->path; f++)
        if (strcmp(f->path, path) == 0) return (const char *)f->data;
    return NULL;
}
