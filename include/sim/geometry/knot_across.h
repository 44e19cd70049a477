/* knot_across.h: the knot that two open threads make together (a bend: a
 * reef or granny knot joining two threads), named by closing the two into
 * one curve far outside the knot and naming that curve (sim/geometry/knot.h).
 *
 * The closure (knot_across.c argues it): each end of thread a is joined to
 * the end of thread b on the same side of the line from a's ends to b's
 * ends, the two joins passing far outside around opposite sides. A reef
 * knot of two threads then reads as the square knot, the granny as the
 * granny, and two threads that are not tied together as the unknot. */
#ifndef RODSIM_SIM_KNOT_ACROSS_H
#define RODSIM_SIM_KNOT_ACROSS_H

#include <stddef.h>

#include "sim/geometry/knot.h"

/* Points of the closed curve two threads of na and nb nodes make (the
 * work array of rod_knot_identify_across holds this many x 3). */
int rod_knot_across_points(int na, int nb);

/* Closes a (na x 3, m) and b (nb x 3, m) into one closed polygon in work
 * (rod_knot_across_points(na, nb) x 3): a from its first node to its last,
 * a join, b in the direction the join gives, the join back. Returns the
 * point count, or -1 (fewer than 2 nodes in a rod, or a non-finite point).
 * *b_reversed (may be NULL): 1 when b is taken from its last node;
 * *b_first (may be NULL): the point where b starts in work. */
int rod_knot_close_across(const double *a, int na, const double *b, int nb, double *work,
                          int *b_reversed, int *b_first);

/* The knot of the closed curve of a and b (the fields of rod_knot; name
 * "unknot" for threads not tied together). scratch as rod_knot_identify_in
 * (NULL: one for this call). Returns 0, or -1 with a message in err. */
int rod_knot_identify_across(rod_knot_scratch *scratch, const double *a, int na,
                             const double *b, int nb, double *work, rod_knot *out, char *err,
                             size_t errlen);

#endif
