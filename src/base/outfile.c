/* outfile.c: atomic output files (see outfile.h). */
#include "base/outfile.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Temporary names in flight, for the signal handler. A fixed table: the
 * handler may not allocate, and a run has only a handful of outputs. */
#define OUTFILE_SLOTS 64
static char pending[OUTFILE_SLOTS][OUTFILE_PATH_MAX];
static volatile sig_atomic_t pending_used[OUTFILE_SLOTS];

int outfile_mkdirs(const char *dir, char *err, size_t errlen)
{
    char buf[OUTFILE_PATH_MAX];
    if (snprintf(buf, sizeof buf, "%s", dir) >= (int)sizeof buf) {
        snprintf(err, errlen, "%s: path too long", dir);
        return -1;
    }
    for (char *p = buf + 1;; p++) {
        if (*p == '/' || *p == '\0') {
            char keep = *p;
            *p = '\0';
            if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
                snprintf(err, errlen, "%s: cannot create directory: %s", buf, strerror(errno));
                return -1;
            }
            *p = keep;
            if (keep == '\0') break;
        }
    }
    return 0;
}

static int make_parent(const char *path, char *err, size_t errlen)
{
    const char *slash = strrchr(path, '/');
    if (!slash || slash == path) return 0;
    char dir[OUTFILE_PATH_MAX];
    snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    return outfile_mkdirs(dir, err, errlen);
}

int outfile_reserve(outfile *f, const char *path, char *err, size_t errlen)
{
    memset(f, 0, sizeof *f);
    f->slot = -1;
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    int dirlen = slash ? (int)(slash - path + 1) : 0;
    if (*base == '\0' || snprintf(f->path, sizeof f->path, "%s", path) >= (int)sizeof f->path) {
        snprintf(err, errlen, "%s: not a usable output file name", path);
        return -1;
    }
    /* keep the extension last: libavformat picks the container from it */
    const char *ext = strrchr(base, '.');
    if (!ext) ext = "";
    if (snprintf(f->tmp_path, sizeof f->tmp_path, "%.*s.%.*s.tmp%ld%s", dirlen, path,
                 (int)(strlen(base) - strlen(ext)), base, (long)getpid(), ext) >=
        (int)sizeof f->tmp_path) {
        snprintf(err, errlen, "%s: path too long", path);
        return -1;
    }
    if (make_parent(path, err, errlen)) return -1;
    for (int i = 0; i < OUTFILE_SLOTS; i++) {
        if (pending_used[i]) continue;
        memcpy(pending[i], f->tmp_path, sizeof f->tmp_path);
        pending_used[i] = 1;
        f->slot = i;
        break;
    }
    return 0;
}

int outfile_open(outfile *f, const char *path, char *err, size_t errlen)
{
    if (outfile_reserve(f, path, err, errlen)) return -1;
    f->fp = fopen(f->tmp_path, "wb");
    if (!f->fp) {
        snprintf(err, errlen, "%s: cannot write: %s", path, strerror(errno));
        outfile_abort(f);
        return -1;
    }
    return 0;
}

static void release_slot(outfile *f)
{
    if (f->slot >= 0) pending_used[f->slot] = 0;
    f->slot = -1;
}

int outfile_commit(outfile *f, char *err, size_t errlen)
{
    if (f->fp) {
        int bad = ferror(f->fp);
        if (fclose(f->fp) != 0) bad = 1;
        f->fp = NULL;
        if (bad) {
            snprintf(err, errlen, "%s: write failed (disk full?)", f->path);
            outfile_abort(f);
            return -1;
        }
    }
    if (rename(f->tmp_path, f->path) != 0) {
        snprintf(err, errlen, "%s: cannot rename finished file into place: %s", f->path,
                 strerror(errno));
        outfile_abort(f);
        return -1;
    }
    release_slot(f);
    f->tmp_path[0] = '\0';
    return 0;
}

void outfile_abort(outfile *f)
{
    if (f->fp) fclose(f->fp);
    f->fp = NULL;
    if (f->tmp_path[0]) unlink(f->tmp_path);
    f->tmp_path[0] = '\0';
    release_slot(f);
}

static void on_signal(int sig)
{
    for (int i = 0; i < OUTFILE_SLOTS; i++)
        if (pending_used[i]) unlink(pending[i]);
    (void)sig;
    _exit(130);
}

void outfile_install_signal_cleanup(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}
