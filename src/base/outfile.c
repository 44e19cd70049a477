/* outfile.c: atomic output files and the transaction of a run (see outfile.h). */
#define _GNU_SOURCE /* O_TMPFILE, AT_EMPTY_PATH (Linux) */
#include "base/outfile.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

/* Named temporaries in flight, for the signal handler. A fixed table: the
 * handler may not allocate, and a run has only a handful of outputs. */
#define OUTFILE_SLOTS 64
static char pending[OUTFILE_SLOTS][OUTFILE_PATH_MAX];
static volatile sig_atomic_t pending_used[OUTFILE_SLOTS];
/* Directories of frames being written, removed by the handler too. */
#define OUTFILE_DIR_SLOTS 4
static char watched[OUTFILE_DIR_SLOTS][OUTFILE_PATH_MAX];
static volatile sig_atomic_t watched_used[OUTFILE_DIR_SLOTS];
static pthread_mutex_t slots_lock = PTHREAD_MUTEX_INITIALIZER;

/* The open transaction of this thread: files set aside until it commits. */
#define OUTFILE_TRANSACTION_MAX 16
static _Thread_local struct {
    int open;
    int count;
    outfile files[OUTFILE_TRANSACTION_MAX];
} transaction;

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

int outfile_check_dir(const char *dir, char *err, size_t errlen)
{
    char buf[OUTFILE_PATH_MAX];
    if (dir[0] == '\0' || snprintf(buf, sizeof buf, "%s", dir) >= (int)sizeof buf) {
        snprintf(err, errlen, "'%s': not a usable directory name", dir);
        return -1;
    }
    /* every prefix that exists must be a directory; the deepest one writable */
    char deepest[OUTFILE_PATH_MAX] = ".";
    for (char *p = buf + 1;; p++) {
        if (*p == '/' || *p == '\0') {
            char keep = *p;
            *p = '\0';
            struct stat st;
            if (stat(buf, &st) == 0) {
                if (!S_ISDIR(st.st_mode)) {
                    snprintf(err, errlen, "%s: is a file, not a directory", buf);
                    return -1;
                }
                snprintf(deepest, sizeof deepest, "%s", buf);
            } else if (errno != ENOENT) {
                snprintf(err, errlen, "%s: %s", buf, strerror(errno));
                return -1;
            }
            *p = keep;
            if (keep == '\0') break;
        }
    }
    if (access(deepest, W_OK | X_OK) != 0) {
        snprintf(err, errlen, "%s: cannot write there: %s", deepest, strerror(errno));
        return -1;
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

static int claim_slot(const char *name)
{
    int slot = -1;
    pthread_mutex_lock(&slots_lock);
    for (int i = 0; i < OUTFILE_SLOTS && slot < 0; i++) {
        if (pending_used[i]) continue;
        snprintf(pending[i], sizeof pending[i], "%s", name);
        pending_used[i] = 1;
        slot = i;
    }
    pthread_mutex_unlock(&slots_lock);
    return slot;
}

static void release_slot(int *slot)
{
    if (*slot >= 0) pending_used[*slot] = 0;
    *slot = -1;
}

/* ".STEM.tmpPID.EXT" beside path: the extension stays last (libavformat and
 * viewers go by it); outfile_remove_stale() recognises the pattern. */
static int hidden_name(char *out, size_t outlen, const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    int dirlen = slash ? (int)(slash - path + 1) : 0;
    const char *ext = strrchr(base, '.');
    if (!ext || ext == base) ext = "";
    return snprintf(out, outlen, "%.*s.%.*s.tmp%ld%s", dirlen, path,
                    (int)(strlen(base) - strlen(ext)), base, (long)getpid(), ext) >= (int)outlen
               ? -1
               : 0;
}

int outfile_in_place(const char *path)
{
    struct stat st;
    return strncmp(path, "/dev/", 5) == 0 || strncmp(path, "/proc/", 6) == 0 ||
           (stat(path, &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode));
}

int outfile_reserve(outfile *f, const char *path, char *err, size_t errlen)
{
    memset(f, 0, sizeof *f);
    f->slot = -1;
    f->fd = -1;
    f->watch = -1;
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    if (*base == '\0' || snprintf(f->path, sizeof f->path, "%s", path) >= (int)sizeof f->path) {
        snprintf(err, errlen, "%s: not a usable output file name", path);
        return -1;
    }
    /* A device, a pipe or a socket (/dev/null, /dev/stdout, a FIFO) is
     * written in place, as the bytes come: a finished file renamed over it
     * would put a regular file where the device was (as root, /dev/null
     * itself). A symbolic link to a file keeps its link: the file it names
     * is the one replaced. */
    struct stat st;
    if (outfile_in_place(path)) {
        f->direct = 1;
        snprintf(f->tmp_path, sizeof f->tmp_path, "%s", path);
        return 0;
    }
    char *real = NULL;
    if (lstat(path, &st) == 0 && S_ISLNK(st.st_mode) && (real = realpath(path, NULL)) != NULL) {
        int fits = snprintf(f->path, sizeof f->path, "%s", real) < (int)sizeof f->path;
        free(real);
        if (!fits) {
            snprintf(err, errlen, "%s: path too long", path);
            return -1;
        }
        path = f->path;
        slash = strrchr(path, '/');
    }
    if (make_parent(path, err, errlen)) return -1;
    char dir[OUTFILE_PATH_MAX];
    if (!slash) snprintf(dir, sizeof dir, ".");
    else if (slash == path) snprintf(dir, sizeof dir, "/");
    else snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    /* a nameless file in the destination's directory: the kernel removes it
     * when the process ends, even by kill -9 */
    f->fd = open(dir, O_TMPFILE | O_RDWR | O_CLOEXEC, 0666);
    if (f->fd >= 0) {
        snprintf(f->tmp_path, sizeof f->tmp_path, "/proc/self/fd/%d", f->fd);
        if (access(f->tmp_path, W_OK) == 0) return 0;
        close(f->fd); /* no /proc: fall back to a name */
        f->fd = -1;
    }
    if (hidden_name(f->tmp_path, sizeof f->tmp_path, path)) {
        snprintf(err, errlen, "%s: path too long", path);
        return -1;
    }
    f->slot = claim_slot(f->tmp_path);
    return 0;
}

int outfile_open(outfile *f, const char *path, char *err, size_t errlen)
{
    if (outfile_reserve(f, path, err, errlen)) return -1;
    if (f->fd >= 0) {
        /* a second descriptor for stdio: f->fd stays open for the link */
        int copy = dup(f->fd);
        f->fp = copy >= 0 ? fdopen(copy, "wb") : NULL;
        if (!f->fp && copy >= 0) close(copy);
    } else {
        f->fp = fopen(f->tmp_path, "wb");
    }
    if (!f->fp) {
        snprintf(err, errlen, "%s: cannot write: %s", path, strerror(errno));
        outfile_abort(f);
        return -1;
    }
    return 0;
}

/* Closes the FILE, reporting a write error (a full disk shows up here). */
static int finish_writing(outfile *f, char *err, size_t errlen)
{
    if (!f->fp) return 0;
    int bad = ferror(f->fp);
    if (fclose(f->fp) != 0) bad = 1;
    f->fp = NULL;
    if (bad) {
        snprintf(err, errlen, "%s: write failed (disk full?)", f->path);
        return -1;
    }
    return 0;
}

/* Gives a nameless file a hidden name beside its destination. */
static int stage(outfile *f, char *err, size_t errlen)
{
    if (f->fd < 0) return 0; /* already named */
    char name[OUTFILE_PATH_MAX];
    if (hidden_name(name, sizeof name, f->path)) {
        snprintf(err, errlen, "%s: path too long", f->path);
        return -1;
    }
    unlink(name); /* a leftover of a process with our PID */
    int slot = claim_slot(name);
    if (linkat(AT_FDCWD, f->tmp_path, AT_FDCWD, name, AT_SYMLINK_FOLLOW) != 0 &&
        linkat(f->fd, "", AT_FDCWD, name, AT_EMPTY_PATH) != 0) {
        snprintf(err, errlen, "%s: cannot give the finished file a name: %s", f->path,
                 strerror(errno));
        release_slot(&slot);
        return -1;
    }
    close(f->fd);
    f->fd = -1;
    snprintf(f->tmp_path, sizeof f->tmp_path, "%s", name);
    f->slot = slot;
    return 0;
}

/* Renames a finished directory over its final name; an older one there is
 * moved aside first and removed after. */
static int place_dir(outfile *f)
{
    if (rename(f->tmp_path, f->path) == 0) return 0;
    if (errno != ENOTEMPTY && errno != EEXIST) return -1;
    char old[OUTFILE_PATH_MAX + 8];
    snprintf(old, sizeof old, "%s.old", f->tmp_path);
    if (rename(f->path, old) != 0) return -1;
    if (rename(f->tmp_path, f->path) != 0) {
        int saved = errno;
        rename(old, f->path);
        errno = saved;
        return -1;
    }
    outfile_remove_flat_dir(old);
    return 0;
}

int outfile_dir_open(outfile *f, const char *dir, char *err, size_t errlen)
{
    memset(f, 0, sizeof *f);
    f->fd = -1;
    f->slot = -1;
    f->watch = -1;
    if (snprintf(f->path, sizeof f->path, "%s", dir) >= (int)sizeof f->path ||
        hidden_name(f->tmp_path, sizeof f->tmp_path, dir)) {
        snprintf(err, errlen, "%s: path too long", dir);
        return -1;
    }
    if (make_parent(dir, err, errlen)) return -1;
    outfile_remove_flat_dir(f->tmp_path); /* a leftover of a process with our PID */
    if (mkdir(f->tmp_path, 0777) != 0) {
        snprintf(err, errlen, "%s: cannot create directory: %s", f->tmp_path, strerror(errno));
        return -1;
    }
    f->is_dir = 1;
    f->watch = outfile_watch_dir(f->tmp_path);
    return 0;
}

/* Names every file of the list (staged, then renamed), with SIGINT and
 * SIGTERM held off so that a signal finds either none or all of them named. */
static int place_all(outfile *files, int count, char *err, size_t errlen)
{
    sigset_t hold, old;
    sigemptyset(&hold);
    sigaddset(&hold, SIGINT);
    sigaddset(&hold, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &hold, &old);
    int status = 0;
    /* what would make a rename fail is found before any rename: a file where
     * a directory goes or the reverse */
    for (int i = 0; i < count && !status; i++) {
        struct stat st;
        if (stat(files[i].path, &st) == 0 && !S_ISDIR(st.st_mode) != !files[i].is_dir) {
            snprintf(err, errlen, "%s: is %s, cannot be replaced by the %s", files[i].path,
                     files[i].is_dir ? "a file" : "a directory",
                     files[i].is_dir ? "frame directory" : "output file");
            status = -1;
        }
    }
    for (int i = 0; i < count && !status; i++) status = stage(&files[i], err, errlen);
    for (int i = 0; i < count && !status; i++) {
        if (files[i].is_dir ? place_dir(&files[i]) != 0
                                : rename(files[i].tmp_path, files[i].path) != 0) {
            snprintf(err, errlen, "%s: cannot rename the finished file into place: %s",
                     files[i].path, strerror(errno));
            status = -1;
            break;
        }
        files[i].tmp_path[0] = '\0';
        release_slot(&files[i].slot);
        if (files[i].is_dir) outfile_forget_dir(files[i].watch);
        files[i].watch = -1;
        files[i].is_dir = 0;
    }
    if (status)
        for (int i = 0; i < count; i++) outfile_abort(&files[i]);
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    return status;
}

int outfile_commit(outfile *f, char *err, size_t errlen)
{
    if (finish_writing(f, err, errlen)) {
        outfile_abort(f);
        return -1;
    }
    if (f->direct) { /* written in place: nothing to name */
        f->tmp_path[0] = '\0';
        return 0;
    }
    if (transaction.open) {
        if (transaction.count == OUTFILE_TRANSACTION_MAX) {
            snprintf(err, errlen, "%s: too many outputs in one run", f->path);
            outfile_abort(f);
            return -1;
        }
        transaction.files[transaction.count++] = *f;
        /* the transaction owns the temporary now */
        f->fd = -1;
        f->slot = -1;
        f->watch = -1;
        f->tmp_path[0] = '\0';
        return 0;
    }
    return place_all(f, 1, err, errlen);
}

void outfile_abort(outfile *f)
{
    if (f->fp) fclose(f->fp);
    f->fp = NULL;
    if (f->fd >= 0) close(f->fd); /* nameless: the kernel frees it */
    f->fd = -1;
    if (f->tmp_path[0] && f->slot >= 0) unlink(f->tmp_path);
    if (f->tmp_path[0] && f->is_dir) outfile_remove_flat_dir(f->tmp_path);
    if (f->is_dir) outfile_forget_dir(f->watch);
    f->watch = -1;
    f->is_dir = 0;
    f->tmp_path[0] = '\0';
    release_slot(&f->slot);
}

void outfile_transaction_begin(void)
{
    transaction.open = 1;
    transaction.count = 0;
}

int outfile_transaction_active(void)
{
    return transaction.open;
}

int outfile_transaction_commit(char *err, size_t errlen)
{
    int status = place_all(transaction.files, transaction.count, err, errlen);
    transaction.open = 0;
    transaction.count = 0;
    return status;
}

void outfile_transaction_abort(void)
{
    for (int i = 0; i < transaction.count; i++) outfile_abort(&transaction.files[i]);
    transaction.open = 0;
    transaction.count = 0;
}

/* ------------------------------------------------------------ directories */

/* getdents64 records (the kernel's layout) */
struct dirent_record {
    uint64_t inode;
    int64_t offset;
    unsigned short length;
    unsigned char type;
    char name[];
};

/* Async-signal-safe: open, getdents64, unlinkat, close, rmdir only. */
int outfile_remove_flat_dir(const char *dir)
{
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return -1;
    _Alignas(8) char buf[4096];
    for (;;) {
        long got = syscall(SYS_getdents64, fd, buf, sizeof buf);
        if (got <= 0) break;
        int removed = 0;
        for (long at = 0; at < got;) {
            struct dirent_record *e = (struct dirent_record *)(void *)(buf + at);
            at += e->length;
            if (strcmp(e->name, ".") && strcmp(e->name, "..") && unlinkat(fd, e->name, 0) == 0)
                removed++;
        }
        if (!removed) break; /* nothing more we can remove */
        lseek(fd, 0, SEEK_SET);
    }
    close(fd);
    return rmdir(dir);
}

/* The same, again while another thread may still be adding files to it. */
static void remove_flat_dir_repeatedly(const char *dir)
{
    for (int attempt = 0; attempt < 1000; attempt++)
        if (outfile_remove_flat_dir(dir) == 0 || errno != ENOTEMPTY) return;
}

int outfile_watch_dir(const char *dir)
{
    int handle = -1;
    pthread_mutex_lock(&slots_lock);
    for (int i = 0; i < OUTFILE_DIR_SLOTS && handle < 0; i++) {
        if (watched_used[i]) continue;
        snprintf(watched[i], sizeof watched[i], "%s", dir);
        watched_used[i] = 1;
        handle = i;
    }
    pthread_mutex_unlock(&slots_lock);
    return handle;
}

void outfile_forget_dir(int handle)
{
    if (handle >= 0 && handle < OUTFILE_DIR_SLOTS) watched_used[handle] = 0;
}

/* The PID of a hidden temporary ".NAME.tmpPID" or ".NAME.tmpPID.EXT", or 0. */
static long temporary_pid(const char *name)
{
    if (name[0] != '.') return 0;
    const char *tmp = NULL;
    for (const char *p = strstr(name, ".tmp"); p; p = strstr(p + 1, ".tmp")) tmp = p;
    if (!tmp || tmp == name) return 0;
    const char *digits = tmp + 4;
    char *end;
    long pid = strtol(digits, &end, 10);
    if (end == digits || pid <= 0 || (*end != '\0' && *end != '.')) return 0;
    return pid;
}

int outfile_remove_stale(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) return 0;
    int removed = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        long pid = temporary_pid(e->d_name);
        if (pid <= 0 || pid == (long)getpid()) continue;
        if (kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue; /* alive, or not ours to judge */
        char path[OUTFILE_PATH_MAX + 256];
        if (snprintf(path, sizeof path, "%s/%s", dir, e->d_name) >= (int)sizeof path) continue;
        if (unlink(path) == 0 || outfile_remove_flat_dir(path) == 0) removed++;
    }
    closedir(d);
    return removed;
}

static volatile sig_atomic_t defer_allowed, deferring, deferred;

void outfile_signal_defer_allow(int on) { defer_allowed = on; }

int outfile_signal_defer(int on)
{
    deferring = on && defer_allowed;
    return deferred;
}

int outfile_stop_signal(void) { return deferred; }

const char *outfile_signal_name(int sig) { return sig == SIGINT ? "SIGINT (Ctrl-C)" : "SIGTERM"; }

int outfile_stop_message(double t, char *out, size_t n)
{
    if (!deferred) return 0;
    snprintf(out, n, "stopped by %s at t = %g s", outfile_signal_name(deferred), t);
    return 1;
}

static void on_signal(int sig)
{
    if (deferring && !deferred) {
        /* the step loop ends at its next step and the command says the rest */
        deferred = sig;
        static const char noted[] =
            "rodsim: stopping at the next step (the same signal again stops at once)\n";
        if (write(STDERR_FILENO, noted, sizeof noted - 1) < 0) {
            /* nothing to do: the stop still happens */
        }
        return;
    }
    for (int i = 0; i < OUTFILE_SLOTS; i++)
        if (pending_used[i]) unlink(pending[i]);
    for (int i = 0; i < OUTFILE_DIR_SLOTS; i++)
        if (watched_used[i]) remove_flat_dir_repeatedly(watched[i]);
    /* nameless temporaries vanish with the process; a line says why it
     * stopped (write(2): safe in a handler, unlike stdio) */
    static const char stopped_int[] =
        "rodsim: stopped by SIGINT (Ctrl-C): exit 130, unfinished outputs removed\n";
    static const char stopped_term[] =
        "rodsim: stopped by SIGTERM: exit 143, unfinished outputs removed\n";
    const char *line = sig == SIGINT ? stopped_int : stopped_term;
    size_t length = sig == SIGINT ? sizeof stopped_int - 1 : sizeof stopped_term - 1;
    if (write(STDERR_FILENO, line, length) < 0) {
        /* nothing to do: the exit status still says it */
    }
    _exit(128 + sig);
}

void outfile_install_signal_cleanup(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaddset(&sa.sa_mask, SIGINT);
    sigaddset(&sa.sa_mask, SIGTERM);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}
