/* tissue_mesh.h: the tetrahedra of a tissue pad (linear tets, 4 nodes).
 *
 * A structured grid over the box, graded: spacing element_size away from
 * the wound, element_size * wound_refine at it (growing by 1.3 per layer
 * between), every hex cut into the same 6 tets around its main diagonal
 * (Kuhn's split: neighbours share face diagonals, so the mesh conforms).
 * Across the slit's plane and from its bottom edge (a crack front) the
 * spacing starts at that times wound_tip_refine and grows by 1.3 per layer.
 * A wound is a slit along x or y in the top face to a depth: the grid has a
 * plane through it, and the nodes on the slit (its rim and ends excluded,
 * an end on the pad's face included: the slit cut through) are duplicated, the tets on the far side using the copies, so the two
 * faces separate. Quadratic tets add a node at each edge's midpoint (the
 * slit's edges are distinct on its two sides, so their midpoints are too). */
#ifndef RODSIM_SIM_TISSUE_TISSUE_MESH_H
#define RODSIM_SIM_TISSUE_TISSUE_MESH_H

#include <stddef.h>

#include "sim/tissue/tissue_config.h"

typedef struct tissue_mesh {
    int nodes;
    int tets;
    int nodes_per_tet;     /* 4 (linear) or 10 (quadratic: corners, then the midpoints
                              of the edges 01 02 03 12 13 23) */
    double *rest;          /* (nodes x 3), m: reference positions */
    int *tet;              /* (tets x nodes_per_tet): node indices, positive volume order */
    unsigned char *held;   /* (nodes): 1 on a face the config holds */
    int slit_pairs;        /* pairs of nodes that coincide at rest across the slit */
    int *slit_node;        /* (slit_pairs): the node on the near side (smaller coordinate) */
    int *slit_twin;        /* (slit_pairs): its copy on the far side */
    int slit_axis;         /* 0: the slit's faces face x; 1: they face y; -1: no wound */
    int grid[3];           /* grid points along x y z */
    double *axis[3];       /* (grid[i]), m: the grid's coordinates along x y z */
} tissue_mesh;

/* The grid's point counts along x y z for a config (no allocation); -1 with
 * a message naming the key when the wound does not fit. */
int tissue_mesh_count(const tissue_config *c, int grid[3], int *slit_nodes, char *err,
                      size_t errlen);

/* Builds the mesh of a checked config; 0, or -1 (out of memory) with a message.
 * tissue_mesh_destroy frees it (also after a failure). */
int tissue_mesh_build(const tissue_config *c, tissue_mesh *m, char *err, size_t errlen);
void tissue_mesh_destroy(tissue_mesh *m);

#endif
