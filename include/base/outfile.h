/* outfile.h: output files that appear whole or not at all.
 *
 * Everything rodsim writes (CSV, PNG, MP4) goes first to a nameless file the
 * kernel removes when the process ends, however it ends (O_TMPFILE in the
 * destination's directory; its bytes are reachable by the path
 * /proc/self/fd/N for writers that open by name, such as libavformat). Only a
 * complete file is linked under its final name. Where O_TMPFILE is not
 * available (another file system), a hidden name ".STEM.tmpPID.EXT" beside
 * the destination is used instead; SIGINT/SIGTERM remove it, and
 * outfile_remove_stale() removes those that a killed process (kill -9) left.
 *
 * A transaction groups the outputs of one run: while it is open, committing a
 * file on this thread only sets it aside; outfile_transaction_commit() gives
 * them all their names at once (SIGINT and SIGTERM held off meanwhile), and
 * outfile_transaction_abort() or a signal discards them all.
 *
 * A destination that is a device, a pipe or a socket (/dev/null, /dev/stdout)
 * is written in place instead (nothing can be renamed over a device), and a
 * symbolic link to a file keeps its link: the file it names is replaced.
 */
#ifndef RODSIM_OUTFILE_H
#define RODSIM_OUTFILE_H

#include <stddef.h>
#include <stdio.h>

#define OUTFILE_PATH_MAX 1024

typedef struct outfile {
    char path[OUTFILE_PATH_MAX];     /* final name */
    char tmp_path[OUTFILE_PATH_MAX]; /* where the bytes go until commit (may be /proc/self/fd/N) */
    FILE *fp;                        /* open on tmp_path; NULL for outfile_reserve() */
    int fd;                          /* the O_TMPFILE descriptor, -1 for a named temporary */
    int slot;                        /* index in the cleanup registry of named temporaries */
    int is_dir;                      /* made by outfile_dir_open() */
    int watch;                       /* its outfile_watch_dir() handle, or -1 */
    int direct;                      /* a device or pipe: written in place (tmp_path = path) */
} outfile;

/* Creates the parent directory if needed and opens a temporary file beside
 * `path` for writing ("wb"). Returns 0, or -1 with a message in err. */
int outfile_open(outfile *f, const char *path, char *err, size_t errlen);
/* Like outfile_open but does not open a FILE: for writers that open the name
 * themselves (libavformat). Use f->tmp_path. */
int outfile_reserve(outfile *f, const char *path, char *err, size_t errlen);

/* 1 when path is written in place, not staged and renamed: a device, a
 * pipe or a socket (/dev/..., /proc/..., or an existing non-regular file). */
int outfile_in_place(const char *path);
/* Closes (if open) and gives the file its final name; inside a transaction on
 * this thread, sets it aside for outfile_transaction_commit(). */
int outfile_commit(outfile *f, char *err, size_t errlen);
/* Closes (if open) and discards the temporary file. Safe to call twice. */
void outfile_abort(outfile *f);

/* Opens the transaction of this thread (one at a time). */
void outfile_transaction_begin(void);
/* 1 when this thread has a transaction open. */
int outfile_transaction_active(void);
/* Names every file committed since outfile_transaction_begin(): all appear or,
 * on an error (reported in err), none. Closes the transaction. */
int outfile_transaction_commit(char *err, size_t errlen);
/* Discards every file set aside and closes the transaction. */
void outfile_transaction_abort(void);

/* Creates a directory and its parents (like mkdir -p). 0 or -1 with err. */
int outfile_mkdirs(const char *dir, char *err, size_t errlen);

/* Checks that `dir` is a directory or can be made (each existing ancestor a
 * directory). 0, or -1 with a message naming the path only: the caller adds
 * the option or field that named it. Makes nothing. */
int outfile_check_dir(const char *dir, char *err, size_t errlen);

/* Removes from `dir` the hidden temporaries (".NAME.tmpPID[.EXT]", files or
 * directories) whose process PID no longer exists. Returns how many. */
int outfile_remove_stale(const char *dir);

/* Installs SIGINT/SIGTERM handlers that discard every temporary file not yet
 * committed, print a line naming the signal on stderr, then exit with status
 * 128 + the signal (130 for SIGINT, 143 for SIGTERM). Call once from main. */
void outfile_install_signal_cleanup(void);

/* A step loop that can end cleanly (rodsim run's): once allowed
 * (outfile_signal_defer_allow(1), by the command), a SIGINT/SIGTERM that
 * arrives while the loop holds the window open (outfile_signal_defer(1))
 * is only noted, with a line on stderr; the loop ends at its next step and
 * the command writes its summary, removes its unfinished outputs and exits
 * 128 + the signal. A second signal, or one outside the window, acts at
 * once as above. outfile_signal_defer returns the noted signal (0: none);
 * outfile_stop_signal reads it. */
void outfile_signal_defer_allow(int on);
int outfile_signal_defer(int on);
int outfile_stop_signal(void);

/* "SIGINT (Ctrl-C)" or "SIGTERM". */
const char *outfile_signal_name(int sig);

/* The noted signal's stop in words, "stopped by SIGTERM at t = T s", into
 * out: 1, or 0 (out untouched) when none was noted. */
int outfile_stop_message(double t, char *out, size_t n);

/* A directory of outputs (a frame sequence): made under a hidden name
 * ".NAME.tmpPID" beside `dir` (f->tmp_path; the signal handler removes it),
 * then renamed over `dir` (replacing an older one) by outfile_commit(), or,
 * inside a transaction, with the rest. outfile_abort() removes it. */
int outfile_dir_open(outfile *f, const char *dir, char *err, size_t errlen);

/* Registers a directory of temporary files (a frame sequence being written)
 * for removal by the signal handler; returns a handle for
 * outfile_forget_dir(), or -1 when the table is full. */
int outfile_watch_dir(const char *dir);
void outfile_forget_dir(int handle);
/* Removes a directory and the files directly in it. 0, or -1. */
int outfile_remove_flat_dir(const char *dir);

#endif
