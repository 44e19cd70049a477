/* test_needle_track.c: the needle's track through the tissue
 * (surface.track_spacing). A needle's back (the thread's pinned tip) is
 * driven along a circle of radius R = 5.52 mm in the plane x = 0, centred
 * R - D over the skin of a tissue box (D = 3.5 mm, the bite's depth: the
 * needle enters and leaves at y = -+sqrt(R^2 - (R - D)^2) = 5.14 mm), then
 * drawn up and on; the thread's root is free. With track_spacing = 2 mm:
 *  - the thread's deepest point between the entry and the exit lies at the
 *    circle's depth D (hand value, not the code's) within 10 %;
 *  - each track point lies on the circle (its distance to the centre
 *    within 0.3 mm of R), the thread passes the holes and the track points
 *    in order (their arc lengths increase entry, track, exit) and through
 *    each (its centreline within 0.05 mm);
 *  - the run is stable: every step succeeds, and no joint of the thread
 *    turns by more than 90 degrees (no kink).
 * Without the key (0) the thread between the holes is the straight chord:
 * its deepest point is within a diameter of the skin (printed beside). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "sim/rod_set.h"
#include "test.h"
#include "test_needle_bite.h"
#include "test_process.h"

/* m: the distance from p to the centreline (nodes x 3) */
static double to_centreline(const double *x, int nodes, const double p[3])
{
    double best = INFINITY;
    for (int i = 0; i + 1 < nodes; i++) {
        double d[3], q[3], e[3];
        v3_sub(d, &x[3 * i + 3], &x[3 * i]);
        v3_sub(q, p, &x[3 * i]);
        double u = v3_dot(q, d) / v3_dot(d, d);
        u = u < 0 ? 0 : u > 1 ? 1 : u;
        v3_copy(e, &x[3 * i]);
        v3_axpy(e, u, d);
        v3_sub(e, p, e);
        best = fmin(best, v3_norm(e));
    }
    return best;
}

typedef struct outcome {
    int ok, holes, tracks, in_order;
    double deepest;      /* m: the thread's deepest point between entry and exit, under z = 0 */
    double worst_circle; /* m: a track point's largest distance off the circle */
    double worst_pass;   /* m: the centreline's largest distance from a puncture */
    double worst_turn;   /* rad: the largest turn at a joint, every step */
    double cpu;          /* s */
} outcome;

static outcome run_bite(double spacing)
{
    outcome o = {0};
    char scene[256], path[256], err[1024];
    snprintf(scene, sizeof scene, "%s/bite.ini", test_dir());
    snprintf(path, sizeof path, "%s/back.csv", test_dir());
    char text[2048];
    if (bite_scene(path, "nodes = 41\n", spacing, text, sizeof text)) return o;
    FILE *f = fopen(scene, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
    ini_doc *doc = ini_parse(scene, text, err, sizeof err);
    rod_set set;
    rod_set_run run;
    int ok = doc && scene_read_rods(doc, &set, err, sizeof err) == 0;
    ini_destroy(doc);
    if (!check(ok, "the bite's scene (track_spacing %g m) reads (%s)", spacing, ok ? "ok" : err))
        return o;
    if (!check(rod_set_run_create(&set, &run, err, sizeof err) == 0, "run made (%s)", err)) {
        rod_set_release(&set);
        return o;
    }
    const rod_model *m = &set.model[0];
    rod_state *s = run.state[0];
    const double h = 0.001, c0 = (double)clock() / CLOCKS_PER_SEC;
    const int steps = (int)lround((BITE_SWEEP + BITE_DRAW) / h);
    rod_report report;
    o.ok = 1;
    for (int i = 1; i <= steps && o.ok; i++) {
        if (rod_set_step(&set, &run, h, &report) != ROD_OK) {
            check(0, "track_spacing %g m: step %d (t = %.3f s): %s", spacing, i, i * h,
                  report.message);
            o.ok = 0;
            for (int k = 0; k < s->puncture_count; k++)
                printf("# puncture %d%s: s %.3f mm at (%.3f, %.3f, %.3f) mm\n", k,
                       s->puncture[k].track ? " (track)" : "", 1e3 * s->puncture[k].s,
                       1e3 * s->puncture[k].point[0], 1e3 * s->puncture[k].point[1],
                       1e3 * s->puncture[k].point[2]);
        }
        for (int k = 1; k + 1 < m->nodes; k++) {
            double a[3], b[3];
            v3_sub(a, &s->position[3 * k], &s->position[3 * k - 3]);
            v3_sub(b, &s->position[3 * k + 3], &s->position[3 * k]);
            double c = v3_dot(a, b) / (v3_norm(a) * v3_norm(b));
            o.worst_turn = fmax(o.worst_turn, acos(c > 1 ? 1 : c < -1 ? -1 : c));
        }
    }
    o.cpu = (double)clock() / CLOCKS_PER_SEC - c0;
    /* the holes and the track points, in the order they were made */
    double entry_s = -1.0, exit_s = -1.0, last_s = -INFINITY;
    const double zc = BITE_RADIUS - BITE_DEPTH;
    o.in_order = 1;
    for (int k = 0; k < s->puncture_count; k++) {
        const rod_puncture_state *p = &s->puncture[k];
        if (p->track) {
            o.tracks++;
            const double off = hypot(p->point[1], p->point[2] - zc) - BITE_RADIUS;
            o.worst_circle = fmax(o.worst_circle, fabs(off));
        } else {
            o.holes++;
            if (entry_s < 0.0) entry_s = p->s;
            else exit_s = p->s;
        }
        o.in_order &= p->s > last_s;
        last_s = p->s;
        o.worst_pass = fmax(o.worst_pass, to_centreline(s->position, m->nodes, p->point));
    }
    o.deepest = 0.0;
    for (int k = 0; k < m->nodes && exit_s > entry_s; k++)
        if (k * m->ds > entry_s && k * m->ds < exit_s) o.deepest = fmax(o.deepest, -s->position[3 * k + 2]);
    rod_set_run_destroy(&run);
    rod_set_release(&set);
    return o;
}

/* A bad track_spacing is refused, naming the key and what is accepted. */
static void bad_spacing(const char *surface, const char *want, const char *what)
{
    char text[512], err[1024] = "";
    snprintf(text, sizeof text,
             "[rod]\nlength = 0.04\ndiameter = 0.00018\ndensity = 1140\nyoungs_modulus = "
             "1.5e9\nshear_modulus = 0.55e9\nnodes = 41\norigin = 0 0 0.001\n[surface]\n"
             "shape = box\ncenter = 0 0 -0.004\nsize = 0.04 0.06 0.008\n%s", surface);
    ini_doc *doc = ini_parse("bad.ini", text, err, sizeof err);
    rod_set set;
    const int read = doc ? scene_read_rods(doc, &set, err, sizeof err) : -1;
    if (read == 0) rod_set_release(&set);
    ini_destroy(doc);
    check(read != 0 && strstr(err, "track_spacing") && strstr(err, want),
          "%s is refused: %s", what, read ? err : "(accepted)");
}

int main(void)
{
    bad_spacing("tissue = yes\ntrack_spacing = -0.001\n", ">= 0", "a negative track_spacing");
    bad_spacing("track_spacing = 0.002\n", "tissue = yes", "a track in a surface not tissue");
    const double spacing = 0.002;
    outcome on = run_bite(spacing), off = run_bite(0.0);
    if (on.ok) {
        check(on.holes == 2 && on.tracks >= 3,
              "with the track (%.1f mm): %d holes (expected 2, entry and exit) and %d track "
              "points (expected at least 3 along the 11 mm under the skin)",
              1e3 * spacing, on.holes, on.tracks);
        const double rel = fabs(on.deepest - BITE_DEPTH) / BITE_DEPTH;
        check(rel <= 0.10,
              "with the track the thread's deepest point between the holes is %.3f mm under "
              "the skin, the needle's circle %.3f mm: relative error %.3f (at most 0.10)",
              1e3 * on.deepest, 1e3 * BITE_DEPTH, rel);
        check(on.worst_circle <= 3e-4,
              "the track points on the needle's circle: at most %.3f mm off it (tolerance 0.3)",
              1e3 * on.worst_circle);
        check(on.in_order, "the thread passes the entry, the %d track points and the exit in "
              "order (their arc lengths increase)", on.tracks);
        check(on.worst_pass <= 5e-5, "the centreline through every puncture: at most %.4f mm "
              "from one (tolerance 0.05)", 1e3 * on.worst_pass);
        check(on.worst_turn <= M_PI / 2,
              "no kink with the track: the largest turn at a joint %.1f degrees (at most 90; "
              "without the track %.1f)", on.worst_turn * 180 / M_PI, off.worst_turn * 180 / M_PI);
    }
    if (off.ok) {
        check(off.holes == 2 && off.tracks == 0,
              "without the track: %d holes and %d track points (expected 2 and 0)", off.holes,
              off.tracks);
        check(off.deepest <= 0.25 * BITE_DEPTH,
              "without the track the thread between the holes is the chord (sagging under its "
              "weight): its deepest point %.3f mm under the skin, a quarter of the needle's "
              "circle's %.3f mm at most", 1e3 * off.deepest, 1e3 * BITE_DEPTH);
    }
    printf("# CPU: %.2f s with the track, %.2f s without (%.1f simulated s each)\n", on.cpu,
           off.cpu, BITE_SWEEP + BITE_DRAW);
    return test_finish();
}
