/* cutaway.h: the tissue drawn cut open along a plane ([render] cutaway),
 * pure C: as a textbook draws a stitch in section, the tissue on the
 * viewer's side of the plane is not drawn and its cut face (the cap) is,
 * in the colours of the dermis and the subcutis, so that the needle's path
 * and the thread inside the tissue are seen. The cut is made on the
 * triangles a frame draws (a rigid tissue's once, an elastic pad's each
 * frame, as it is deformed): the cap is the section of the closed surface,
 * its loops filled by ear clipping (docs/decisions: 0076-cutaway). */
#ifndef RODSIM_RENDER_CUTAWAY_H
#define RODSIM_RENDER_CUTAWAY_H

#include "render/mesh.h"
#include "render/options.h"
#include "sim/recording.h"

/* Dermis under the skin's top: this deep (m), at most a quarter of the
 * tissue's height; the subcutis below. */
#define CUTAWAY_DERMIS 0.002
/* The most section segments one surface's cap is made of (a surface cut
 * in more has no cap drawn). */
#define CUTAWAY_MAX_SEGMENTS 4096
/* The room a cut surface of `triangles` triangles needs beyond its own:
 * each cut triangle adds up to 2 vertices and 1 triangle; the cap adds
 * its own. */
#define CUTAWAY_EXTRA_VERTICES(triangles) (9 * (triangles) + CUTAWAY_CAP_VERTICES)
#define CUTAWAY_EXTRA_INDICES(triangles) (12 * (triangles) + 3 * CUTAWAY_CAP_VERTICES)
/* a cap's vertices at most (its triangles cut along the skin's top): what
 * does not fit is left out */
#define CUTAWAY_CAP_VERTICES 16384

/* The plane of a cut: nothing of a tissue on the normal's side is drawn. */
typedef struct cutaway_plane {
    int on;            /* 0: no cut */
    double point[3];   /* m, global: a point of the plane */
    double normal[3];  /* unit, towards the side not drawn (the eye's) */
} cutaway_plane;

/* The plane o->cutaway asks for, for the run rec (as recorded): the given
 * plane; or (yes) the upright plane (holding z) through the stitch's
 * punctures (those of the frame with the most), fitted to them seen from
 * above (across the wound for one stitch, whose punctures lie on a line
 * across it), its normal turned towards the eye (o's camera direction);
 * with no puncture (or all at one x y), the upright plane through the first
 * tissue surface's centre facing the eye. */
void cutaway_resolve(cutaway_plane *c, const rod_recording *rec, const render_options *o);

/* What making a cap uses, made once (no allocation per frame). */
typedef struct cutaway_scratch {
    double *segment;   /* (CUTAWAY_MAX_SEGMENTS x 6), m: each segment's ends */
    int *next;         /* (CUTAWAY_MAX_SEGMENTS) the segment that follows, -1: none */
    int *loop;         /* (CUTAWAY_MAX_SEGMENTS) a loop's segments, then its ear list */
    double *flat;      /* (CUTAWAY_MAX_SEGMENTS x 2), m: a loop's points in the plane */
    double *top;       /* (CUTAWAY_MAX_SEGMENTS x 2), m: the skin's top along the section,
                          points (u along across, z), u increasing */
    int top_count;
    double across[3];  /* unit: the plane's horizontal (u) */
} cutaway_scratch;
/* NULL when out of memory. */
cutaway_scratch *cutaway_scratch_create(void);
void cutaway_scratch_destroy(cutaway_scratch *s);

/* The dermis's thickness (m) in a tissue whose bounds are lo .. hi (m):
 * CUTAWAY_DERMIS, at most a quarter of its height. */
double cutaway_dermis(const double lo[3], const double hi[3]);

/* Cuts the triangles m->indices[first_index ..] (one closed surface,
 * wound counter-clockwise seen from outside): what lies on the normal's
 * side is removed and its cap added (the section's loops, facing the
 * normal): the dermis down to `dermis` (m) below the skin's top (the
 * section's upper edge, the wound's mouth bridged), the subcutis below.
 * m needs CUTAWAY_EXTRA_* room beyond. */
void cutaway_cut(render_mesh *m, int first_index, const cutaway_plane *c, double dermis,
                 cutaway_scratch *s);
/* Removes what lies on the normal's side from the triangles
 * m->indices[first_index ..] (no cap: the punctures' discs, the wound). */
void cutaway_clip(render_mesh *m, int first_index, const cutaway_plane *c);

#endif
