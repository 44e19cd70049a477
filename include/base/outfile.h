/* outfile.h: output files that appear whole or not at all.
 *
 * Everything rodsim writes (CSV, PNG, MP4) is written under a temporary name
 * in the destination's directory and renamed over the final name only when
 * complete. A failure, or SIGINT/SIGTERM, removes the temporary file, so no
 * half-written file is ever left in out/.
 */
#ifndef RODSIM_OUTFILE_H
#define RODSIM_OUTFILE_H

#include <stddef.h>
#include <stdio.h>

#define OUTFILE_PATH_MAX 1024

typedef struct outfile {
    char path[OUTFILE_PATH_MAX];     /* final name */
    char tmp_path[OUTFILE_PATH_MAX]; /* where the bytes go until commit */
    FILE *fp;                        /* open on tmp_path; NULL for outfile_reserve() */
    int slot;                        /* index in the cleanup registry */
} outfile;

/* Creates the parent directory if needed and opens a temporary file beside
 * `path` for writing ("wb"). Returns 0, or -1 with a message in err. */
int outfile_open(outfile *f, const char *path, char *err, size_t errlen);
/* Like outfile_open but does not open the file: for writers that open the
 * name themselves (libavformat, libpng). Use f->tmp_path. */
int outfile_reserve(outfile *f, const char *path, char *err, size_t errlen);
/* Closes (if open) and renames the temporary file to the final name. */
int outfile_commit(outfile *f, char *err, size_t errlen);
/* Closes (if open) and removes the temporary file. Safe to call twice. */
void outfile_abort(outfile *f);

/* Creates a directory and its parents (like mkdir -p). 0 or -1 with err. */
int outfile_mkdirs(const char *dir, char *err, size_t errlen);

/* Installs SIGINT/SIGTERM handlers that remove every temporary file not yet
 * committed or aborted, then exit with status 130. Call once from main. */
void outfile_install_signal_cleanup(void);

#endif
