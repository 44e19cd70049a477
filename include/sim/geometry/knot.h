/* knot.h: the knot type of a rod's centreline, from the Alexander
 * polynomial of a projection's crossings. Pure geometry: points in, a name out.
 *
 * An open polygon (a thread) has no knot type of its own: it is closed far
 * outside the knot first (knot.c says how), which does not change the type of
 * a knot tied away from the ends. The Alexander polynomial Delta(t) is exact
 * (integer coefficients); it names the knots of up to 6 crossings and the
 * composites listed in knot.c, but not everything: it is 1 for a few
 * non-trivial knots (e.g. the Conway knot 11n34), it does not see a knot's
 * chirality, and it cannot tell the square knot from the granny (both
 * (t^2 - t + 1)^2). The signature (from the Goeritz matrix of the same
 * diagram) tells those two apart, and a knot from its mirror image when it is
 * not 0 (Rolfsen's convention: the right-handed trefoil has -2): the name
 * then says the hand. */
#ifndef RODSIM_SIM_KNOT_H
#define RODSIM_SIM_KNOT_H

#include <stddef.h>

/* Most crossings a projection may have: the determinant costs ~crossings^3
 * (bench_knot: 3 ms at 77 crossings, 0.19 s at 363); a polygon whose every
 * tried projection has more is refused. */
#define ROD_KNOT_MAX_CROSSINGS 400
/* Most points of a polygon (the crossing search is near linear). */
#define ROD_KNOT_MAX_POINTS 2000000
/* Coefficients kept of the normalised polynomial (degree <= this - 1). */
#define ROD_KNOT_MAX_TERMS 64

typedef struct rod_knot {
    char name[96];            /* "unknot", "trefoil, right-handed", "square knot ...",
                                 "granny knot ..., left-handed", ..., or "unknown (Delta =
                                 ...)"; a knot whose signature is not 0 ends in ",
                                 right-handed" (signature < 0) or ", left-handed" (> 0) */
    int terms;                /* coefficients in `coefficient`: degree + 1 */
    long long coefficient[ROD_KNOT_MAX_TERMS]; /* Delta(t) = sum c_k t^k, normalised:
                                 lowest term constant and positive (trefoil 1 -1 1) */
    long long determinant;    /* |Delta(-1)|: 1 unknot, 3 trefoil, 5 figure-eight */
    int signature;            /* sigma(K) (Gordon-Litherland): 0 unknot, figure-eight and
                                 square knot, +-2 trefoil, +-4 granny; sign: handedness */
    int has_signature;        /* 0: the diagram's faces were not understood */
    int crossing_number;      /* of the knot named (0 unknot, 3 trefoil, 8 surgeon's knot);
                                 an unnamed one's lower bound: degree of Delta + 1 */
    int crossings;            /* of the projection used (closure included) */
    int writhe;               /* sum of the crossings' signs in that projection */
    double direction[3];      /* unit: the projection's direction */
    int tries;                /* projection directions tried (1 unless degenerate) */
} rod_knot;

/* The knot type of an open polygon (nodes x 3, m), closed far outside it.
 * Returns 0, or -1 with a message in err (too few or non-finite points, too
 * many crossings, a polygon that passes through itself). out is filled on 0. */
int rod_knot_identify(const double *points, int nodes, rod_knot *out, char *err,
                      size_t errlen);

/* The same for a closed polygon: the last point joins the first (do not
 * repeat the first point at the end). */
int rod_knot_identify_closed(const double *points, int nodes, rod_knot *out, char *err,
                             size_t errlen);

/* Scratch memory kept between calls (a run identifies every output frame):
 * with it, a call allocates nothing once the scratch has grown to the
 * largest call's need. Not shared between threads. */
typedef struct rod_knot_scratch rod_knot_scratch;
rod_knot_scratch *rod_knot_scratch_create(void); /* NULL out of memory */
void rod_knot_scratch_destroy(rod_knot_scratch *scratch);

/* rod_knot_identify (closed = 0) or rod_knot_identify_closed (closed = 1)
 * with a scratch (NULL: one for this call only). */
int rod_knot_identify_in(rod_knot_scratch *scratch, const double *points, int nodes, int closed,
                         rod_knot *out, char *err, size_t errlen);

/* How an open polygon's ends are taken out to the far sphere where they are
 * joined: radially from the centroid (rod_knot_identify's), along each
 * end's own last segment, or each straight away from the other end. A knot
 * tied away from its ends, the tails leaving it, has the same type under
 * all three; a knot still forming (a tail ending among its turns, or only
 * just through them) may not: the closures finish it differently. */
enum { ROD_KNOT_CLOSE_RADIAL, ROD_KNOT_CLOSE_TANGENT, ROD_KNOT_CLOSE_APART, ROD_KNOT_CLOSURES };

/* rod_knot_identify_in of an open polygon (closed = 0) closed by `closure`
 * (ROD_KNOT_CLOSE_...). */
int rod_knot_identify_closure(rod_knot_scratch *scratch, const double *points, int nodes,
                              int closure, rod_knot *out, char *err, size_t errlen);

/* A closed polygon (count x 3, as rod_knot_identify_closed) made of short
 * pieces and long joins far outside (two threads closed into one:
 * knot_across.h): segments [short_ranges[0] = 0, short_ranges[1]) and
 * [short_ranges[2], short_ranges[3]) are short (segment k joins point k to
 * k + 1), the others long: the crossing search then hashes the short ones
 * into cells their size (else the longest segment's) and tests each long
 * one against all. The same result, faster. */
int rod_knot_identify_joined(rod_knot_scratch *scratch, const double *points, int count,
                             const int short_ranges[4], rod_knot *out, char *err, size_t errlen);

/* "1 - t + t^2": Delta(t) of a result, as text. */
void rod_knot_polynomial_text(const rod_knot *k, char *buf, size_t n);

#endif
