/* test_knot_forming.c: the summary's knot of a double throw still forming
 * (cli/knot_track.h). An instrument tie's double throw built here: the
 * long end wound twice round a cylinder (the needle holder's shanks, the x
 * axis), the tail from the bite to the jaws' tip and, as the holder backs
 * out, along the axis through the turns. With the tail at the jaws no knot
 * is named; halfway through the turns the three closures of the open ends
 * disagree (forming: the radial closure alone read a trefoil); drawn out
 * 60 mm, all three name the double throw (the cinquefoil); as a run's
 * frames, one change from the unknot to it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "cli/knot_track.h"
#include "sim/geometry/knot.h"
#include "sim/rod.h"
#include "test.h"

#define MOST 4000

typedef struct shape {
    double p[3 * MOST];
    int n;
} shape;

/* Appends the straight piece to b in steps of at most h (a already in) */
static void line_to(shape *s, const double b[3], double h)
{
    const double *a = &s->p[3 * (s->n - 1)];
    double d[3];
    v3_sub(d, b, a);
    const int steps = (int)ceil(v3_norm(d) / h);
    double a0[3];
    v3_copy(a0, a);
    for (int k = 1; k <= steps && s->n < MOST; k++) {
        for (int e = 0; e < 3; e++) s->p[3 * s->n + e] = a0[e] + d[e] * k / steps;
        s->n++;
    }
}

static void point(shape *s, double x, double y, double z)
{
    s->p[3 * s->n] = x, s->p[3 * s->n + 1] = y, s->p[3 * s->n + 2] = z;
    s->n++;
}

/* mm: the turns' radius, their advance along x per radian, the nodes'
 * spacing, the long end's length */
#define R 3.0
#define C 1.0
#define H 0.5
#define FAR 60.0

/* An instrument tie's double throw: the tail's end at x = tail_x (mm) on
 * the x axis (the needle holder's), the tail along the axis to x = -5 mm
 * (the jaws' tip) and down 15 mm to the bite, the long end up from the
 * bite into two turns round the axis (x 0 to 4 pi C, the holder's
 * shanks), then away to `hand`. Before the throw is made the tail's end is
 * at the jaws (tail_x < -5: the tail not through the turns); the holder
 * backing out draws it along the axis through them (tail_x > 4 pi C:
 * through; far beyond: drawn out). */
static void double_throw(shape *s, double tail_x, const double hand[3])
{
    s->n = 0;
    point(s, tail_x, 0.0, 0.0);
    const double end = 4.0 * M_PI * C;
    const double jaws[3] = {-5.0, 0.0, 0.0}, bite[3] = {-5.0, 0.0, -15.0};
    const double under[3] = {end, R, -15.0}, start[3] = {end, R, 0.0};
    if (tail_x > -5.0) line_to(s, jaws, H);
    else line_to(s, (double[3]){-5.0, 0.0, -1.0}, H); /* the tail's end off the axis */
    line_to(s, bite, H);
    line_to(s, under, H);
    line_to(s, start, H);
    const int per_turn = 60;
    for (int k = 1; k <= 2 * per_turn; k++) { /* from x = end back to x = 0 */
        const double phi = 2.0 * M_PI * k / per_turn;
        point(s, end - C * phi, R * cos(phi), R * sin(phi));
    }
    const double off[3] = {-2.0, R + 5.0, 0.0};
    line_to(s, off, H);
    line_to(s, hand, H);
    for (int i = 0; i < 3 * s->n; i++) s->p[i] *= 1e-3; /* m */
}

/* The tracker's knot of each shape in turn, as a run's frames: the last
 * frame's name in `name`, the changes and forming frames counted */
static void track(const shape *const *frames, int count, char *name, size_t n, int *changes,
                  int *forming)
{
    int most = 0;
    for (int f = 0; f < count; f++) most = frames[f]->n > most ? frames[f]->n : most;
    rod_model m = rod_model_default();
    m.nodes = most;
    m.diameter = 0.0005;
    char err[256] = "";
    snprintf(name, n, "(failed)");
    if (!check(rod_model_derive(&m, err, sizeof err) == 0, "a model of %d nodes %s", most, err))
        return;
    rod_state *st = rod_state_create(&m);
    knot_track k;
    knot_track_init(&k, most);
    for (int f = 0; f < count; f++) {
        st->nodes = frames[f]->n;
        st->time = 0.1 * f;
        memcpy(st->position, frames[f]->p, (size_t)st->nodes * 3 * sizeof(double));
        memset(st->self_force, 0, (size_t)most * 3 * sizeof(double));
        knot_track_frame(&k, &m, st, INFINITY);
    }
    if (k.frames == count) snprintf(name, n, "%s", k.last.name);
    *changes = k.changes;
    *forming = k.forming;
    knot_track_release(&k);
    st->nodes = most;
    rod_state_destroy(st);
    rod_model_release(&m);
}

static void names(const char *what, const shape *s, char *radial, size_t n)
{
    printf("  %s (%d nodes):", what, s->n);
    for (int c = 0; c < ROD_KNOT_CLOSURES; c++) {
        rod_knot k;
        char err[200];
        const int rc = rod_knot_identify_closure(NULL, s->p, s->n, c, &k, err, sizeof err);
        printf(" [%d] %s;", c, rc ? err : k.name);
        if (c == ROD_KNOT_CLOSE_RADIAL) snprintf(radial, n, "%s", rc ? "(failed)" : k.name);
    }
    printf("\n");
}

/* A knot's name: neither the unknot nor a knot still forming */
static int named(const char *name)
{
    return strcmp(name, "unknot") != 0 && strcmp(name, KNOT_FORMING) != 0 &&
           strcmp(name, "(failed)") != 0;
}

int main(void)
{
    static shape s[4];
    char radial[4][96], name[96], premature[2][96];
    const double end = 4.0 * M_PI * C;
    /* the long end leaving the turns sideways (the hand off to the side), or
     * along the holder (the hand beyond it) */
    const double hands[2][3] = {{-2.0, FAR, 0.0}, {FAR, R + 5.0, 0.0}};
    const double tails[4] = {-8.0, 2.0 * M_PI * C, end + 3.0, end + FAR};
    const char *what[4] = {"the tail at the jaws", "the tail halfway through the turns",
                           "the tail 3 mm past the turns", "the tail drawn out 60 mm"};
    for (int h = 0; h < 2; h++) {
        const char *hand = h ? "the hand along the holder" : "the hand to the side";
        int changes = 0, forming = 0;
        for (int t = 0; t < 4; t++) {
            double_throw(&s[t], tails[t], hands[h]);
            names(what[t], &s[t], radial[t], sizeof radial[t]);
            const shape *one[1] = {&s[t]};
            track(one, 1, name, sizeof name, &changes, &forming);
            printf("    %s, %s: radial closure %s; the summary's %s\n", hand, what[t], radial[t],
                   name);
            if (t == 0)
                check(!named(name), "%s, %s: no knot named (%s)", hand, what[t], name);
            if (t == 1)
                check(strcmp(name, KNOT_FORMING) == 0, "%s, %s: %s (the closures disagree)",
                      hand, what[t], name);
            if ((h == 0 && t == 1) || (h == 1 && t == 2))
                memcpy(premature[h], radial[t], sizeof premature[h]);
            if (t == 3)
                check(strncmp(name, "cinquefoil", 10) == 0 && strcmp(name, radial[t]) == 0,
                      "%s, %s: the double throw named, %s (the radial closure's %s)", hand,
                      what[t], name, radial[t]);
        }
        /* the four as a run's frames: one change, unknot to the double throw */
        const shape *run[4] = {&s[0], &s[1], &s[2], &s[3]};
        track(run, 4, name, sizeof name, &changes, &forming);
        check(changes == 1 && strncmp(name, "cinquefoil", 10) == 0,
              "%s, the four as frames: %d change(s) (1: a forming frame is none), the last %s, "
              "%d forming", hand, changes, name, forming);
    }
    /* the radial closure alone (the summary's former rule) named the throws
     * before they were made: the tail halfway, the hand to the side, a
     * trefoil; the tail 3 mm past the turns, the hand along the holder, the
     * finished throw's cinquefoil while the closure away from the other end
     * still finds the unknot */
    check(named(premature[0]) && named(premature[1]),
          "the radial closure alone names the unfinished throws: %s; %s", premature[0],
          premature[1]);
    return test_finish();
}
