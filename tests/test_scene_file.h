/* test_scene_file.h: a scene file written by a test, read back as rodsim
 * reads it (the ini parser, then the scene). Header-only, tests only. */
#ifndef RODSIM_TEST_SCENE_FILE_H
#define RODSIM_TEST_SCENE_FILE_H

#include <stdio.h>

#include "base/ini.h"
#include "sim/scene.h"

/* Reads the scene `name` in directory dir (at most 8 kB) into m; 0, or -1
 * with the reason in err (nothing there: err untouched). */
static inline int test_read_scene_in(const char *dir, const char *name, rod_model *m, char *err,
                                     size_t errlen)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    char text[8192] = "";
    size_t got = fread(text, 1, sizeof text - 1, f);
    text[got] = '\0';
    fclose(f);
    ini_doc *doc = ini_parse(path, text, err, errlen);
    if (!doc) return -1;
    int rc = scene_read_rod(doc, m, err, errlen);
    ini_destroy(doc);
    return rc;
}

#endif
