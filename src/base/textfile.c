/* textfile.c: see textfile.h. */
#include "base/textfile.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void set_error(char *err, size_t errlen, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void set_error(char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || errlen == 0) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

/* "1 MiB (1048576 bytes)", or "1000 bytes" for a limit not in whole MiB. */
static void describe_limit(size_t limit, char *out, size_t outlen)
{
    const size_t mib = (size_t)1 << 20;
    if (limit >= mib && limit % mib == 0)
        snprintf(out, outlen, "%zu MiB (%zu bytes)", limit / mib, limit);
    else
        snprintf(out, outlen, "%zu bytes", limit);
}

/* What a file that is not read is, or NULL for a regular file or a pipe. */
static const char *kind_of(mode_t mode)
{
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return NULL;
}

/* Reads fd to its end into a buffer of at most limit + 2 bytes: the byte
 * past the limit tells a file over it, and the NUL. 0 with *text and
 * *length; -1 with errno (ENOMEM, the read's), or EFBIG past the limit. */
static int read_bounded(int fd, size_t size_hint, size_t limit, char **text, size_t *length)
{
    const size_t most = limit + 2;
    size_t cap = (size_hint < limit ? size_hint : limit) + 2; /* a regular file: its size */
    if (cap < 4096) cap = most < 4096 ? most : 4096;
    char *buf = malloc(cap);
    size_t len = 0;
    if (!buf) return -1;
    for (;;) {
        if (len + 1 == cap) { /* full, and still within the limit: grow */
            size_t next = cap > most / 2 ? most : 2 * cap;
            char *bigger = realloc(buf, next);
            if (!bigger) {
                free(buf);
                errno = ENOMEM;
                return -1;
            }
            buf = bigger;
            cap = next;
        }
        ssize_t got = read(fd, buf + len, cap - 1 - len);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) {
            int saved = errno;
            free(buf);
            errno = saved;
            return -1;
        }
        if (got == 0) break;
        len += (size_t)got;
        if (len > limit) {
            free(buf);
            *length = len;
            errno = EFBIG;
            return -1;
        }
    }
    buf[len] = '\0';
    *text = buf;
    *length = len;
    return 0;
}

/* Refuses what is not 8-bit text: UTF-16 (its byte-order mark), or a NUL. */
static int check_text(const char *path, const char *what, const char *text, size_t len,
                      char *err, size_t errlen)
{
    const unsigned char *u = (const unsigned char *)text;
    if (len >= 2 && ((u[0] == 0xFF && u[1] == 0xFE) || (u[0] == 0xFE && u[1] == 0xFF))) {
        set_error(err, errlen, "%s: the %s file is UTF-16 text; a %s file is UTF-8 or ASCII "
                  "text (save it as UTF-8)", path, what, what);
        return -1;
    }
    const char *nul = memchr(text, '\0', len);
    if (nul) {
        int line = 1;
        for (const char *c = text; c < nul; c++) line += *c == '\n';
        set_error(err, errlen, "%s:%d: a NUL byte (byte %zu of the file): a %s file is text, "
                  "not binary data", path, line, (size_t)(nul - text) + 1, what);
        return -1;
    }
    return 0;
}

/* Opens path for reading what it is known to be: a regular file or a pipe.
 * The descriptor, with *st filled; or -1 with the message. */
static int open_readable(const char *path, const char *what, const char *bound, struct stat *st,
                         char *err, size_t errlen)
{
    /* O_NONBLOCK: opening a device (a serial line) or a FIFO with no writer
     * yet must not wait before it is known what the file is */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        if (errno == ENXIO) /* the name of a Unix socket */
            set_error(err, errlen, "%s: cannot open the %s file: not a file; a %s file is "
                      "text of at most %s", path, what, what, bound);
        else
            set_error(err, errlen, "%s: cannot open the %s file: %s", path, what,
                      strerror(errno));
        return -1;
    }
    if (fstat(fd, st) != 0) {
        set_error(err, errlen, "%s: cannot read the %s file: %s", path, what, strerror(errno));
        close(fd);
        return -1;
    }
    const char *kind = kind_of(st->st_mode);
    if (kind) {
        set_error(err, errlen, "%s: %s, not a %s file; a %s file is text of at most %s", path,
                  kind, what, what, bound);
        close(fd);
        return -1;
    }
    if (S_ISFIFO(st->st_mode)) {
        /* opened again, blocking: it waits for a writer as `cat` would; the
         * first descriptor stays open meanwhile, so a writer that came in
         * between never finds the pipe without a reader */
        int blocking = open(path, O_RDONLY | O_CLOEXEC);
        int saved = errno;
        close(fd);
        if (blocking < 0 || fstat(blocking, st) != 0 || !S_ISFIFO(st->st_mode)) {
            set_error(err, errlen, "%s: cannot read the %s file: %s", path, what,
                      blocking < 0 ? strerror(saved) : "it changed while being opened");
            if (blocking >= 0) close(blocking);
            return -1;
        }
        fd = blocking;
    }
    return fd;
}

int textfile_read(const char *path, const char *what, size_t limit, char **text, size_t *length,
                  char *err, size_t errlen)
{
    *text = NULL;
    if (length) *length = 0;
    char bound[64];
    describe_limit(limit, bound, sizeof bound);
    struct stat st;
    int fd = open_readable(path, what, bound, &st, err, errlen);
    if (fd < 0) return -1;
    if (S_ISREG(st.st_mode) && (unsigned long long)st.st_size > limit) {
        set_error(err, errlen, "%s: the %s file is %lld bytes; a %s file is at most %s", path,
                  what, (long long)st.st_size, what, bound);
        close(fd);
        return -1;
    }
    size_t len = 0;
    int rc = read_bounded(fd, S_ISREG(st.st_mode) ? (size_t)st.st_size : 0, limit, text, &len);
    int saved = errno;
    close(fd);
    if (rc != 0) {
        if (saved == EFBIG)
            set_error(err, errlen, "%s: the %s file goes on past its limit (read no further): "
                      "a %s file is at most %s", path, what, what, bound);
        else
            set_error(err, errlen, "%s: cannot read the %s file: %s", path, what,
                      strerror(saved));
        return -1;
    }
    if (check_text(path, what, *text, len, err, errlen)) {
        free(*text);
        *text = NULL;
        return -1;
    }
    if (length) *length = len;
    return 0;
}

const char *textfile_skip_bom(const char *text)
{
    return strncmp(text, "\xEF\xBB\xBF", 3) == 0 ? text + 3 : text;
}
