/* test_hanging_rods.h: a scene of two named rods hanging apart from their
 * pinned tips (short: 0.3 m, long: 0.5 m, both d = 2 mm, rho = 1000 kg/m^3),
 * whose tip forces at rest are their weights rho A g L, a closed form that
 * does not come from the code: the tests of every surface that names a rod
 * (rodsim live, sweeps, the C API) drive or read them. Header-only, tests
 * only. */
#ifndef RODSIM_TEST_HANGING_RODS_H
#define RODSIM_TEST_HANGING_RODS_H

#include <math.h>
#include <stdio.h>

/* Each rod: from its root (free, below) straight up to its tip (pinned) at
 * z = 0; 0.2 m apart in x, so they never touch. Linear damping 0.03 N s/m^2
 * is about critical for a swing (2 rho A sqrt(g / L) = 0.036 and 0.028 N
 * s/m^2): a rod swung by its tip is at rest within a few seconds. */
#define HANGING_RODS_SCENE                                                                        \
    "[rod short]\nlength = 0.3\ndiameter = 0.002\ndensity = 1000\nyoungs_modulus = 1e8\n"        \
    "shear_modulus = 4e7\nnodes = 16\norigin = 0 0 -0.3\ndirection = 0 0 1\n"                    \
    "[ends short]\nroot = free\ntip = pinned\n"                                                    \
    "[rod long]\nlength = 0.5\ndiameter = 0.002\ndensity = 1000\nyoungs_modulus = 1e8\n"         \
    "shear_modulus = 4e7\nnodes = 26\norigin = 0.2 0 -0.5\ndirection = 0 0 1\n"                  \
    "[ends long]\nroot = free\ntip = pinned\n"                                                     \
    "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.5\n"                                  \
    "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 0.03\n"

/* N: the weight rho A g L of a rod of the scene of length L (m) and density
 * rho (kg/m^3) */
static inline double hanging_rod_weight(double length, double density)
{
    const double radius = 0.001; /* m */
    return density * M_PI * radius * radius * 9.81 * length;
}

/* Writes the scene to path; 0, or -1 */
static inline int hanging_rods_write(const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fputs(HANGING_RODS_SCENE, f);
    return fclose(f) ? -1 : 0;
}

#endif
