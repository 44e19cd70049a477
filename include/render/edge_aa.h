/* edge_aa.h: antialiasing of a picture drawn with one sample per pixel, by
 * its edges: FXAA (T. Lottes, "FXAA", NVIDIA white paper, 2009;
 * the "quality" variant of FXAA 3.11, simplified), in C over RGB bytes.
 * Where the luma changes sharply across a pixel, the edge's direction and
 * its extent along the picture are found, and the pixel is blended with its
 * neighbour across the edge by the fraction the edge's slope says it covers.
 * A flat pixel costs a few operations, an edge's about 30 reads; 4x
 * multisampling costs llvmpipe about as much as the rest of the drawing.
 *
 * A frame is a fixed backdrop with boxes drawn over it (renderer.c): the luma
 * of the backdrop is kept, and only the boxes are looked at. */
#ifndef RODSIM_EDGE_AA_H
#define RODSIM_EDGE_AA_H

#include "render/image.h"

/* Pixels an edge is followed along, each way, at most. */
#define EDGE_AA_REACH 17

typedef struct edge_aa edge_aa;

/* For frames over `backdrop` (its size; not kept) with up to max_boxes
 * boxes each. NULL when out of memory. */
edge_aa *edge_aa_create(const image *backdrop, int max_boxes);
void edge_aa_destroy(edge_aa *a);

/* Smooths the edges inside the boxes (x, y, width, height each, image
 * coordinates, y down, disjoint) of img: the backdrop outside them, what
 * was drawn inside. Reads around a box as far as EDGE_AA_REACH; writes only
 * inside the boxes. No allocation. */
void edge_aa_frame(edge_aa *a, image *img, const int (*boxes)[4], int count);

#endif
