/* test_rod_set.h: a scene of several rods read from text, for tests of
 * the rod set. */
#ifndef RODSIM_TEST_ROD_SET_H
#define RODSIM_TEST_ROD_SET_H

#include <stddef.h>

#include "base/ini.h"
#include "sim/rod_set.h"

/* Reads a scene of [rod NAME] sections from text into set, every key used
 * (an unused key is an error, as `rodsim run` makes it). 0, or -1 with the
 * message in err; set is released on failure. */
static inline int test_read_set(const char *text, rod_set *set, char *err, size_t errlen)
{
    ini_doc *doc = ini_parse("test.ini", text, err, errlen);
    if (!doc) return -1;
    int rc = scene_read_rods(doc, set, err, errlen);
    if (rc == 0 && ini_check_unused(doc, err, errlen)) {
        rod_set_release(set);
        rc = -1;
    }
    ini_destroy(doc);
    return rc;
}

#endif
