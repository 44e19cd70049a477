/* test_needle_bite.h: a needle's bite through tissue, its back (the
 * thread's pinned tip) driven along a circle under the skin and then drawn
 * up and on (tests/sim/test_needle_track.c, tests/sim/test_grid_tissue.c). */
#ifndef RODSIM_TEST_NEEDLE_BITE_H
#define RODSIM_TEST_NEEDLE_BITE_H

#include <math.h>
#include <stddef.h>
#include <stdio.h>

#define BITE_RADIUS 0.005517 /* m: the needle's circle */
#define BITE_DEPTH 0.0035    /* m: the bite's depth under the skin (z = 0) */
#define BITE_SWEEP 1.7       /* s: the needle's back from -85 to +85 degrees */
#define BITE_DRAW 0.5        /* s: then drawn up and on */

/* The needle's back at time t: on the circle, then straight on. */
static inline void bite_back_at(double t, double p[3])
{
    const double zc = BITE_RADIUS - BITE_DEPTH, a0 = -85.0 * M_PI / 180.0;
    double u = t < BITE_SWEEP ? t / BITE_SWEEP : 1.0, a = a0 + u * (-2.0 * a0);
    p[0] = 0.0;
    p[1] = BITE_RADIUS * sin(a);
    p[2] = zc - BITE_RADIUS * cos(a);
    if (t > BITE_SWEEP) { /* up and on, 10 mm along y and 5 mm up */
        const double w = (t - BITE_SWEEP) / BITE_DRAW > 1.0 ? 1.0 : (t - BITE_SWEEP) / BITE_DRAW;
        p[1] += 0.010 * w;
        p[2] += 0.005 * w;
    }
}

/* The bite's scene in text: a 40 mm thread of 0.18 mm, its tip pinned to
 * the needle's back (its path written to `path`, CSV), root free, over a
 * tissue box whose top is the skin; `grid` the [rod] lines nodes (and
 * refine), `spacing` the surface's track_spacing (m). 0, or -1 when the
 * path cannot be written. */
static inline int bite_scene(const char *path, const char *grid, double spacing, char *text,
                             size_t n)
{
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fprintf(f, "t,x,y,z\n");
    for (int i = 0; i <= 110; i++) {
        double t = 0.02 * i, p[3];
        bite_back_at(t, p);
        fprintf(f, "%.6f,%.9f,%.9f,%.9f\n", t, p[0], p[1], p[2]);
    }
    fclose(f);
    double start[3];
    bite_back_at(0.0, start);
    const double length = 0.04;
    snprintf(text, n,
             "[rod]\nlength = %g\ndiameter = 0.00018\ndensity = 1140\nyoungs_modulus = 1.5e9\n"
             "shear_modulus = 0.55e9\n%sorigin = 0 %.9f %.9f\ndirection = 0 1 0\n"
             "[ends]\nroot = free\ntip = pinned\ntip_motion = %s\nneedle = %g\n"
             "[solver]\nscheme = implicit\ndt = 0.001\nduration = %g\n"
             "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 2e-3\n"
             "[surface]\nshape = box\ncenter = 0 0 -0.004\nsize = 0.04 0.06 0.008\n"
             "friction = 0.3\ntissue = yes\ntrack_spacing = %g\n",
             length, grid, start[1] - length, start[2], path, BITE_RADIUS,
             BITE_SWEEP + BITE_DRAW, spacing);
    return 0;
}

#endif
