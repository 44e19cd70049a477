/* test_textfile.c: the bounded whole-file reader (base/textfile.h). A file at
 * its limit is read, one byte over is refused by its size unread; a device
 * (/dev/zero, which never ends) and a directory are refused before any byte is
 * read; a pipe that never ends is read to limit + 1 bytes and refused; every
 * message names the file and the limit. The table lines read from memory
 * (base/textline.h): a byte-order mark skipped, a long line refused. */
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "base/textfile.h"
#include "base/textline.h"
#include "test.h"

static void write_bytes(const char *path, const char *bytes, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f) return;
    fwrite(bytes, 1, n, f);
    fclose(f);
}

/* Reads path with the limit; 0 or -1, the message in err. */
static int read_with(const char *path, size_t limit, char **text, size_t *length, char *err,
                     size_t errlen)
{
    err[0] = '\0';
    return textfile_read(path, "test", limit, text, length, err, errlen);
}

static void test_regular_files(const char *dir)
{
    char path[512], err[512], *text = NULL;
    size_t length = 0;
    snprintf(path, sizeof path, "%s/hundred.txt", dir);
    char hundred[101];
    memset(hundred, 'x', 100);
    hundred[99] = '\n';
    write_bytes(path, hundred, 100);
    check(read_with(path, 100, &text, &length, err, sizeof err) == 0 && length == 100 &&
              text[100] == '\0' && strlen(text) == 100,
          "a 100-byte file at a 100-byte limit is read whole, NUL-terminated (%s)", err);
    free(text);
    check(read_with(path, 99, &text, &length, err, sizeof err) == -1 && text == NULL &&
              strstr(err, path) && strstr(err, "100 bytes") && strstr(err, "at most 99 bytes"),
          "one byte over the limit: refused by its size, naming the file and the limit: '%s'",
          err);

    /* a sparse file of 1 GiB: refused by its size, nothing read */
    snprintf(path, sizeof path, "%s/sparse.txt", dir);
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    int made = fd >= 0 && ftruncate(fd, (off_t)1 << 30) == 0;
    if (fd >= 0) close(fd);
    if (made)
        check(read_with(path, (size_t)1 << 20, &text, NULL, err, sizeof err) == -1 &&
                  strstr(err, "1073741824 bytes") && strstr(err, "1 MiB (1048576 bytes)"),
              "a 1 GiB file against a 1 MiB limit: '%s'", err);
    unlink(path);

    snprintf(path, sizeof path, "%s/empty.txt", dir);
    write_bytes(path, "", 0);
    check(read_with(path, 100, &text, &length, err, sizeof err) == 0 && length == 0 &&
              text[0] == '\0',
          "an empty file reads as an empty text (%s)", err);
    free(text);

    snprintf(path, sizeof path, "%s/nul.txt", dir);
    write_bytes(path, "a\nb\0c\n", 6);
    check(read_with(path, 100, &text, NULL, err, sizeof err) == -1 &&
              strstr(err, "nul.txt:2: a NUL byte (byte 4 of the file)"),
          "a NUL byte: named at its line and byte: '%s'", err);

    snprintf(path, sizeof path, "%s/utf16.txt", dir);
    write_bytes(path, "\xFF\xFEx\0=\0", 6);
    check(read_with(path, 100, &text, NULL, err, sizeof err) == -1 && strstr(err, "UTF-16") &&
              strstr(err, "save it as UTF-8"),
          "UTF-16 text: '%s'", err);

    snprintf(path, sizeof path, "%s/bom.txt", dir);
    write_bytes(path, "\xEF\xBB\xBFx = 1\n", 9);
    if (check(read_with(path, 100, &text, &length, err, sizeof err) == 0 && length == 9,
              "a UTF-8 byte-order mark is read as text (%s)", err)) {
        check(strcmp(textfile_skip_bom(text), "x = 1\n") == 0 &&
                  strcmp(textfile_skip_bom("x"), "x") == 0 &&
                  strcmp(textfile_skip_bom("\xEF\xBB"), "\xEF\xBB") == 0,
              "textfile_skip_bom skips it, and leaves a text without one (or a cut one) as it is");
        free(text);
    }

    snprintf(path, sizeof path, "%s/missing.txt", dir);
    check(read_with(path, 100, &text, NULL, err, sizeof err) == -1 &&
              strstr(err, "missing.txt: cannot open the test file: No such file"),
          "a missing file: '%s'", err);
    const char *names[] = {"hundred.txt", "empty.txt", "nul.txt", "utf16.txt", "bom.txt"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        unlink(path);
    }
}

static void test_not_files(const char *dir)
{
    char err[512], *text = NULL;
    check(read_with("/dev/zero", (size_t)1 << 20, &text, NULL, err, sizeof err) == -1 &&
              text == NULL &&
              strstr(err, "/dev/zero: a character device, not a test file") &&
              strstr(err, "at most 1 MiB (1048576 bytes)"),
          "/dev/zero (never ends): refused unread, naming the limit: '%s'", err);
    check(read_with(dir, 100, &text, NULL, err, sizeof err) == -1 &&
              strstr(err, "a directory, not a test file") && strstr(err, "at most 100 bytes"),
          "a directory: '%s'", err);
}

/* A child writes `total` bytes into a pipe (forever when total is 0); the
 * parent reads it by its name /proc/self/fd/N. */
static void read_pipe(size_t total, size_t limit, int *rc, size_t *length, char *err,
                      size_t errlen)
{
    int fds[2];
    *rc = -2;
    if (pipe(fds) != 0) return;
    pid_t child = fork();
    if (child == 0) {
        close(fds[0]);
        char block[4096];
        memset(block, 'y', sizeof block);
        for (size_t sent = 0; total == 0 || sent < total;) {
            size_t n = total == 0 || total - sent > sizeof block ? sizeof block : total - sent;
            ssize_t w = write(fds[1], block, n);
            if (w <= 0) _exit(0); /* the reader closed: SIGPIPE is ignored below */
            sent += (size_t)w;
        }
        _exit(0);
    }
    close(fds[1]);
    char path[64];
    snprintf(path, sizeof path, "/proc/self/fd/%d", fds[0]);
    char *text = NULL;
    *rc = read_with(path, limit, &text, length, err, errlen);
    free(text);
    close(fds[0]);
    if (child > 0) {
        kill(child, SIGKILL);
        waitpid(child, NULL, 0);
    }
}

static void test_pipes(void)
{
    signal(SIGPIPE, SIG_IGN);
    char err[512];
    int rc;
    size_t length = 0;
    read_pipe(0, 100000, &rc, &length, err, sizeof err);
    check(rc == -1 && strstr(err, "/proc/self/fd/") && strstr(err, "goes on past its limit") &&
              strstr(err, "at most 100000 bytes"),
          "a pipe that never ends: refused after limit + 1 bytes: '%s'", err);
    read_pipe(70000, 100000, &rc, &length, err, sizeof err);
    check(rc == 0 && length == 70000, "a pipe of 70000 bytes, within the limit: read whole "
          "(%zu bytes) (%s)", length, err);
    read_pipe(100001, 100000, &rc, &length, err, sizeof err);
    check(rc == -1 && strstr(err, "goes on past its limit"),
          "a pipe of limit + 1 bytes: refused: '%s'", err);
}

static void test_lines(void)
{
    char line[64], short_line[16], err[256] = "", *text = NULL;
    const char *cursor = "\xEF\xBB\xBF" "x,y,z # header\n\n  # only a comment\r\n1, 2 ,3\r\nlast";
    int line_no = 0;
    int ok = textline_next(&cursor, "t.csv", line, sizeof line, &line_no, &text, err,
                           sizeof err) == 1 && strcmp(text, "x,y,z") == 0 && line_no == 1;
    ok = ok && textline_next(&cursor, "t.csv", line, sizeof line, &line_no, &text, err,
                             sizeof err) == 1 && strcmp(text, "1, 2 ,3") == 0 && line_no == 4;
    ok = ok && textline_next(&cursor, "t.csv", line, sizeof line, &line_no, &text, err,
                             sizeof err) == 1 && strcmp(text, "last") == 0 && line_no == 5;
    ok = ok && textline_next(&cursor, "t.csv", line, sizeof line, &line_no, &text, err,
                             sizeof err) == 0;
    check(ok, "table lines from memory: byte-order mark, comments, blanks, CR LF and a last "
          "line without its newline (%s)", err);
    /* 16-byte buffer: 14 characters fit, 15 do not */
    cursor = "12345678901234\n123456789012345\n";
    line_no = 0;
    ok = textline_next(&cursor, "t.csv", short_line, sizeof short_line, &line_no, &text, err,
                       sizeof err) == 1;
    ok = ok && textline_next(&cursor, "t.csv", short_line, sizeof short_line, &line_no, &text,
                             err, sizeof err) == -1;
    check(ok && strstr(err, "t.csv:2: line longer than 14 characters"),
          "a line of 14 characters fits a 16-byte buffer, one of 15 is refused: '%s'", err);
}

int main(void)
{
    char dir[] = "/tmp/rodsim_textfile_XXXXXX";
    if (!check(mkdtemp(dir) != NULL, "temporary directory")) return test_finish();
    test_regular_files(dir);
    test_not_files(dir);
    test_pipes();
    test_lines();
    rmdir(dir);
    return test_finish();
}
