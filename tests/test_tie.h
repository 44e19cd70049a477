/* test_tie.h: the checks every instrument-tie scene's test makes on its run
 * summary: no instrument driven into the pad, and the needle holder taking the
 * tail by its end. */
#ifndef RODSIM_TEST_TIE_H
#define RODSIM_TEST_TIE_H

#include <string.h>

#include "json.h"
#include "test.h"

/* The summary's warnings name no instrument driven " into the " pad. */
static inline void check_nothing_into_pad(const json_value *warnings)
{
    int into = 0;
    for (int i = 0; warnings && i < warnings->count; i++) {
        const json_value *w = warnings->items[i];
        if (w && w->string && strstr(w->string, " into the ")) into++;
    }
    check(warnings && into == 0, "no instrument goes into the pad (the summary's warnings say "
          "so): %d of %d warnings", into, warnings ? warnings->count : -1);
}

/* The grasp g (the summary's grasps[i]) closes on the thread within 3 mm of
 * its root (the tail's end), between t_from and t_to (s), when the jaws close. */
static inline void check_tail_taken(const json_value *g, double t_from, double t_to)
{
    const json_value *t_on = json_get(g, "t_on"), *s = json_get(g, "s");
    check(t_on && s && t_on->number > t_from && t_on->number < t_to && s->number < 0.003,
          "the holder closes on the tail within 3 mm of its end: t = %.4g s (the jaws close "
          "%g-%g s), s = %.3g mm", t_on ? t_on->number : -1.0, t_from, t_to,
          s ? 1e3 * s->number : -1.0);
}

#endif
