/* fuzz_load_table.c: libFuzzer harness for load tables (CSV, `profile =
 * table FILE`): scene_load_table (sim/scene.c) reads files only, so the
 * input goes into a memory file (memfd, named /proc/self/fd/N: a file on
 * disk made it 100x slower); the table's contract (scene.h, rod.h) is
 * checked, then the tip load is interpolated from it (rod.c) at its times
 * and between them. */
#define _GNU_SOURCE /* memfd_create */
#include <math.h>
#include <sys/mman.h>
#include <unistd.h>

#include "fuzz.h"
#include "sim/rod.h"
#include "sim/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static char path[600];
    static int fd = -1;
    if (fd < 0) {
        fd = memfd_create("table.csv", 0);
        if (fd < 0) abort();
        snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
    }
    if (ftruncate(fd, 0) != 0 || pwrite(fd, data, size, 0) != (ssize_t)size) abort();

    rod_model m = rod_model_default();
    char err[1024] = "";
    if (scene_load_table(path, &m.profile.table, err, sizeof err) != 0) {
        fuzz_require(fuzz_starts(err, path), "a load table message names the file", err);
        fuzz_require(m.profile.table.data == NULL && m.profile.table.rows == 0,
                     "a failed read owns nothing", err);
        return 0;
    }
    const rod_table *t = &m.profile.table;
    fuzz_require(t->rows >= 1 && (t->columns == 2 || t->columns == 7) && t->data != NULL,
                 "a read table has rows of 2 or 7 numbers", NULL);
    for (int r = 0; r < t->rows; r++) {
        for (int c = 0; c < t->columns; c++)
            fuzz_require(isfinite(t->data[r * t->columns + c]), "every number is finite", NULL);
        if (r > 0)
            fuzz_require(t->data[r * t->columns] > t->data[(r - 1) * t->columns],
                         "times strictly increase", NULL);
    }
    m.profile.kind = ROD_PROFILE_TABLE;
    double force[3], moment[3];
    for (int r = 0; r < t->rows && r < 64; r++) {
        double time = t->data[r * t->columns];
        rod_tip_load(&m, time, force, moment);
        rod_tip_load(&m, time + 0.5 * fabs(time) + 1e-3, force, moment);
        (void)rod_profile_factor(&m.profile, time);
    }
    rod_model_release(&m);
    return 0;
}
