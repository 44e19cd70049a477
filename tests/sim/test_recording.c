/* test_recording.c: the frames a run hands to the renderer: the punctures
 * each frame carries (issue 11) survive append and halve, and the memory a
 * recording is charged for is what it allocates. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/recording.h"
#include "test.h"

static void test_punctures(void)
{
    char err[256] = "";
    rod_model m = rod_model_default();
    m.nodes = 11;
    if (!check(rod_model_derive(&m, err, sizeof err) == 0, "model derived%s%s", err[0] ? ": " : "", err)) return;
    rod_state *s = rod_state_create(&m);
    rod_recording *r = rod_recording_create(&m, "punctures", 2);
    if (!check(s && r, "state and recording made")) return;
    /* frames 0..4 with 0, 1, 2, 3 and ROD_MAX_PUNCTURES + 5 punctures (the state's
     * count beyond the array is clamped, never read past it) */
    const int counts[5] = {0, 1, 2, 3, ROD_MAX_PUNCTURES + 5};
    for (int f = 0; f < 5; f++) {
        s->time = 0.1 * f;
        s->puncture_count = counts[f] < ROD_MAX_PUNCTURES ? counts[f] : ROD_MAX_PUNCTURES;
        for (int i = 0; i < ROD_MAX_PUNCTURES; i++) {
            s->puncture[i].point[0] = f;
            s->puncture[i].point[1] = i;
            s->puncture[i].point[2] = -0.01 * i;
        }
        if (f == 4) s->puncture_count = counts[f]; /* a corrupt count must not overrun */
        check(rod_recording_append(r, &m, s) == 0, "frame %d appended (capacity grows from 2)", f);
    }
    int good = 1;
    for (int f = 0; f < 5; f++) {
        const double *p;
        int n = rod_recording_punctures(r, f, &p);
        int want = counts[f] < ROD_MAX_PUNCTURES ? counts[f] : ROD_MAX_PUNCTURES;
        if (n != want) good = 0;
        for (int i = 0; i < n; i++)
            if (p[3 * i] != f || p[3 * i + 1] != i || p[3 * i + 2] != -0.01 * i) good = 0;
    }
    check(good, "each frame keeps its own punctures (0, 1, 2, 3, %d: clamped to the most)",
          ROD_MAX_PUNCTURES);
    rod_recording_halve(r);
    const double *p;
    int n0 = rod_recording_punctures(r, 0, &p), n1 = rod_recording_punctures(r, 1, &p);
    int ok1 = n1 == 2 && p[0] == 2 && p[4] == 1;
    int n2 = rod_recording_punctures(r, 2, &p);
    check(r->frame_count == 3 && n0 == 0 && ok1 && n2 == ROD_MAX_PUNCTURES && p[0] == 4,
          "halved: frames 0, 2, 4 keep their punctures (%d, %d, %d)", n0, n1, n2);
    check(rod_recording_punctures(r, 7, &p) == 0 && p == NULL, "a frame past the end has none");

    /* the bytes charged for `capacity` frames are what reserve() allocates:
     * counted here from the element sizes of each array */
    size_t nodes = (size_t)r->nodes, cap = (size_t)r->capacity;
    double allocated = (double)(cap * sizeof *r->time + cap * nodes * 3 * sizeof *r->position +
                                cap * nodes * 9 * sizeof *r->frame + cap * nodes * sizeof *r->twist +
                                cap * 3 * sizeof *r->tip_force + cap * 3 * sizeof *r->tip_moment +
                                cap * sizeof *r->puncture_count +
                                cap * ROD_MAX_PUNCTURES * 3 * sizeof *r->puncture);
    check_rel("rod_recording_bytes vs the arrays' sizes, bytes", rod_recording_bytes(r->nodes, cap),
              allocated, 1e-15);
    /* a recording made by hand without punctures has none */
    rod_recording bare = *r;
    bare.puncture_count = NULL;
    bare.puncture = NULL;
    check(rod_recording_punctures(&bare, 0, &p) == 0, "no puncture arrays: no punctures");
    rod_recording_destroy(r);
    rod_state_destroy(s);
    rod_model_release(&m);
}

int main(void)
{
    test_punctures();
    return test_finish();
}
