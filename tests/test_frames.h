/* test_frames.h: a rod run's CSV read back by the knot tests (frames of
 * node positions), and where its strands touch, by the tests' own distance
 * between nodes (not the contact code's). */
#ifndef RODSIM_TEST_FRAMES_H
#define RODSIM_TEST_FRAMES_H

#include <stdio.h>
#include <stdlib.h>

/* Reads the CSV of a run of `nodes` nodes (header t,node,s,x,y,z,...):
 * frame times into t, positions into x (frame k at x + 3 nodes k), at most
 * max_frames; returns the frames (rows into *rows). */
static inline int test_read_frames(const char *csv, int nodes, int max_frames, double *t, double *x,
                                   int *rows)
{
    FILE *f = fopen(csv, "r");
    int frames = 0;
    char line[1024];
    *rows = 0;
    if (f && fgets(line, sizeof line, f)) {
        while (fgets(line, sizeof line, f)) {
            double tt, s, px, py, pz;
            int node;
            if (sscanf(line, "%lf,%d,%lf,%lf,%lf,%lf", &tt, &node, &s, &px, &py, &pz) != 6) break;
            if (node == 0) {
                if (frames == max_frames) break;
                t[frames++] = tt;
            }
            if (node < 0 || node >= nodes || frames == 0) break;
            double *p = &x[(size_t)(frames - 1) * 3 * (size_t)nodes + 3 * (size_t)node];
            p[0] = px, p[1] = py, p[2] = pz;
            (*rows)++;
        }
    }
    if (f) fclose(f);
    return frames;
}

/* 1 when node i lies within 1.15 diameters of a node more than 5 along the
 * rod: strands touching there. */
static inline int test_touching(const double *x, int nodes, double diameter, int i)
{
    for (int j = 0; j < nodes; j++) {
        if (abs(i - j) < 6) continue;
        double d2 = 0.0;
        for (int k = 0; k < 3; k++) d2 += (x[3 * i + k] - x[3 * j + k]) * (x[3 * i + k] - x[3 * j + k]);
        if (d2 < 1.15 * 1.15 * diameter * diameter) return 1;
    }
    return 0;
}

/* The lowest node where strands touch, or -1 when none does. */
static inline int test_lowest_touching(const double *x, int nodes, double diameter)
{
    for (int i = 0; i < nodes; i++)
        if (test_touching(x, nodes, diameter, i)) return i;
    return -1;
}

/* The arc (m) between the outermost nodes where strands touch (the rope in
 * the knot); 0 when none does. */
static inline double test_knot_arc(const double *x, int nodes, double diameter, double ds)
{
    int lo = test_lowest_touching(x, nodes, diameter), hi = -1;
    for (int i = nodes - 1; lo >= 0 && i >= lo && hi < 0; i--)
        if (test_touching(x, nodes, diameter, i)) hi = i;
    return lo < 0 ? 0.0 : (hi - lo) * ds;
}

#endif
