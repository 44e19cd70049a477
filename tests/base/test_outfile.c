/* test_outfile.c: output files appear whole or not at all. A file being
 * written has no name in its directory (O_TMPFILE), a commit gives it its
 * name (replacing an older file), a transaction names all its files at once
 * or none, the temporaries a killed process left are removed by the next run
 * (and those of a live process kept), -o's check tells a file from a
 * directory, and a device or a link is written through, never replaced. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "base/outfile.h"
#include "test.h"
#include "test_process.h"

static char dir[] = "/tmp/rodsim_outfile_XXXXXX";

static int entries(void)
{
    return test_dir_entries(dir);
}

/* The whole content of a small file, "" when it cannot be read. */
static const char *content(const char *path)
{
    static char buf[256];
    buf[0] = '\0';
    FILE *f = fopen(path, "r");
    if (f) {
        size_t got = fread(buf, 1, sizeof buf - 1, f);
        buf[got] = '\0';
        fclose(f);
    }
    return buf;
}

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static void test_single_file(void)
{
    char path[128], err[256];
    snprintf(path, sizeof path, "%s/a.csv", dir);
    write_text(path, "old\n");
    outfile f;
    int opened = outfile_open(&f, path, err, sizeof err) == 0;
    if (!check(opened, "outfile_open %s: %s", path, opened ? "" : err)) return;
    fputs("new\n", f.fp);
    check(entries() == 1 && strcmp(content(path), "old\n") == 0,
          "while written: the directory holds only the old file (%d entries), unchanged",
          entries());
    check(f.fd >= 0, "the temporary is nameless (O_TMPFILE, fd %d, written through %s)", f.fd,
          f.tmp_path);
    int committed = outfile_commit(&f, err, sizeof err) == 0;
    check(committed && entries() == 1 && strcmp(content(path), "new\n") == 0,
          "commit replaces the old file by the new one (%d entries, '%s')", entries(),
          content(path));
    unlink(path);

    /* abort leaves nothing */
    opened = outfile_open(&f, path, err, sizeof err) == 0;
    if (opened) fputs("never\n", f.fp);
    outfile_abort(&f);
    check(opened && entries() == 0, "abort leaves nothing (%d entries)", entries());

    /* a writer that opens by name (libavformat) writes through /proc/self/fd/N */
    opened = outfile_reserve(&f, path, err, sizeof err) == 0;
    FILE *by_name = opened ? fopen(f.tmp_path, "wb") : NULL;
    if (by_name) {
        fputs("by name\n", by_name);
        fclose(by_name);
    }
    committed = by_name && outfile_commit(&f, err, sizeof err) == 0;
    check(committed && strcmp(content(path), "by name\n") == 0,
          "a file written by its temporary's name is committed whole ('%s')", content(path));
    unlink(path);
}

static void test_transaction(void)
{
    char csv[128], png[128], frames[128], frame[OUTFILE_PATH_MAX + 16], err[256];
    snprintf(csv, sizeof csv, "%s/run.csv", dir);
    snprintf(png, sizeof png, "%s/run.png", dir);
    snprintf(frames, sizeof frames, "%s/run_frames", dir);
    for (int commit = 0; commit < 2; commit++) {
        outfile_transaction_begin();
        outfile a, b, d;
        int ok = outfile_open(&a, csv, err, sizeof err) == 0;
        if (ok) fputs("t,x\n", a.fp);
        ok = ok && outfile_commit(&a, err, sizeof err) == 0;
        ok = ok && outfile_open(&b, png, err, sizeof err) == 0;
        if (ok) fputs("png", b.fp);
        ok = ok && outfile_commit(&b, err, sizeof err) == 0;
        ok = ok && outfile_dir_open(&d, frames, err, sizeof err) == 0;
        if (ok) {
            snprintf(frame, sizeof frame, "%s/00000.png", d.tmp_path);
            write_text(frame, "frame");
        }
        ok = ok && outfile_commit(&d, err, sizeof err) == 0;
        /* before the transaction ends: only the hidden frame directory */
        int before = entries();
        if (commit) {
            ok = ok && outfile_transaction_commit(err, sizeof err) == 0;
            snprintf(frame, sizeof frame, "%s/00000.png", frames);
            check(ok && before == 1 && entries() == 3 && strcmp(content(csv), "t,x\n") == 0 &&
                      strcmp(content(frame), "frame") == 0,
                  "transaction commit: %d hidden entry before, then CSV, PNG and frames (%d "
                  "entries)",
                  before, entries());
        } else {
            outfile_transaction_abort();
            check(ok && before == 1 && entries() == 0,
                  "transaction abort: nothing named before (%d hidden), nothing after (%d)",
                  before, entries());
        }
    }
    test_remove_tree(frames);
    unlink(csv);
    unlink(png);
}

static void test_stale(void)
{
    /* a PID that has ended: a child that exited */
    pid_t dead = fork();
    if (dead == 0) _exit(0);
    waitpid(dead, NULL, 0);
    char stale_file[160], stale_dir[160], stale_frame[192], live[160], plain[160];
    snprintf(stale_file, sizeof stale_file, "%s/.suture.tmp%d.mp4", dir, (int)dead);
    snprintf(stale_dir, sizeof stale_dir, "%s/.suture_frames.tmp%d", dir, (int)dead);
    snprintf(stale_frame, sizeof stale_frame, "%s/00000.png", stale_dir);
    snprintf(live, sizeof live, "%s/.suture.tmp%d.csv", dir, (int)getppid());
    snprintf(plain, sizeof plain, "%s/.notes.tmpfile", dir);
    write_text(stale_file, "x");
    mkdir(stale_dir, 0777);
    write_text(stale_frame, "x");
    write_text(live, "x");
    write_text(plain, "x");
    int removed = outfile_remove_stale(dir);
    check(removed == 2 && access(stale_file, F_OK) != 0 && access(stale_dir, F_OK) != 0 &&
              access(live, F_OK) == 0 && access(plain, F_OK) == 0,
          "stale temporaries of dead PID %d removed (%d: the file and the frame directory); a "
          "live process's and a name not of the pattern kept",
          (int)dead, removed);
    unlink(live);
    unlink(plain);
}

static void test_check_dir(void)
{
    char file[128], below[160], fresh[160], err[256];
    snprintf(file, sizeof file, "%s/a_file", dir);
    snprintf(below, sizeof below, "%s/a_file/out", dir);
    snprintf(fresh, sizeof fresh, "%s/new/out", dir);
    write_text(file, "x");
    check(outfile_check_dir(file, err, sizeof err) == -1 && strstr(err, "not a directory"),
          "-o naming a file is refused: %s", err);
    check(outfile_check_dir(below, err, sizeof err) == -1, "-o below a file is refused: %s",
          err);
    check(outfile_check_dir(fresh, err, sizeof err) == 0 && access(fresh, F_OK) != 0,
          "-o naming a directory still to make is accepted, and nothing is made");
    check(outfile_check_dir(dir, err, sizeof err) == 0, "-o naming a directory is accepted");
    unlink(file);
}

/* A destination that is a device or a pipe is written in place: a link in
 * the test's folder to /dev/null stays a link to the device (before: the
 * commit renamed a regular file over the link; `--csv /dev/null` as root
 * put a regular file where /dev/null was). A link to a file keeps its link
 * and the file it names gets the new content. */
static void test_devices_and_links(void)
{
    char sink[128], real[128], link[128], err[256];
    snprintf(sink, sizeof sink, "%s/sink", dir);
    snprintf(real, sizeof real, "%s/real.csv", dir);
    snprintf(link, sizeof link, "%s/link.csv", dir);
    if (!check(symlink("/dev/null", sink) == 0, "a link %s to /dev/null", sink)) return;
    outfile f;
    int opened = outfile_open(&f, sink, err, sizeof err) == 0;
    if (opened) fputs("nothing\n", f.fp);
    int committed = opened && outfile_commit(&f, err, sizeof err) == 0;
    struct stat st, dev;
    check(committed && lstat(sink, &st) == 0 && S_ISLNK(st.st_mode) && stat(sink, &dev) == 0 &&
              S_ISCHR(dev.st_mode) && entries() == 1,
          "writing to a link to /dev/null: committed %d, still a link to the character device "
          "(%d entries)",
          committed, entries());
    unlink(sink);

    write_text(real, "old\n");
    if (!check(symlink("real.csv", link) == 0, "a link %s to real.csv", link)) return;
    opened = outfile_open(&f, link, err, sizeof err) == 0;
    if (opened) fputs("new\n", f.fp);
    committed = opened && outfile_commit(&f, err, sizeof err) == 0;
    check(committed && lstat(link, &st) == 0 && S_ISLNK(st.st_mode) &&
              strcmp(content(real), "new\n") == 0 && entries() == 2,
          "writing to a link to a file: the link stays (%d), the file reads '%s' (new), %d entries",
          committed && lstat(link, &st) == 0 && S_ISLNK(st.st_mode), content(real), entries());
    unlink(link);
    unlink(real);
}

int main(void)
{
    if (!check(mkdtemp(dir) != NULL, "temporary directory")) return test_finish();
    test_single_file();
    test_transaction();
    test_stale();
    test_check_dir();
    test_devices_and_links();
    test_remove_tree(dir);
    return test_finish();
}
