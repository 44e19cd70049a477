/* surface.h: the geometry of the rigid obstacles a rod touches (scene
 * [surface], rod_surface in sim/rod.h): distance, normal, nearest point and
 * the first crossing of a moving point, each for the solid grown by the
 * rod's radius (the centreline touches the grown solid when the rod's
 * surface touches the obstacle). Every solid is convex, so its signed
 * distance is a convex function along any segment: the swept test below
 * relies on that. */
#ifndef RODSIM_SIM_CONTACT_SURFACE_H
#define RODSIM_SIM_CONTACT_SURFACE_H

#include <stddef.h>

#include "sim/rod_types.h"

/* Signed distance (m) from p to the solid grown by `grow` (m): > 0 outside,
 * < 0 inside. `normal` (may be NULL) gets the unit outward normal at the
 * nearest point of the grown surface, `nearest` (may be NULL) that point. */
double rod_surface_gap(const rod_surface *s, const double p[3], double grow, double normal[3],
                       double nearest[3]);

/* The first point where a point moving from a (outside the grown solid) to
 * b enters it: returns 1 with the fraction f of the way (0..1), the point and
 * the outward normal there; 0 when the segment stays outside. */
int rod_surface_sweep(const rod_surface *s, const double a[3], const double b[3], double grow,
                      double *f, double point[3], double normal[3]);

/* The curvature of the grown solid's surface at its point p (on it, outward
 * normal n): the Hessian of the signed distance there, 1/m, row-major.
 * (I - n n^T - e e^T) / R on a cylinder's side or a box's rounded edge
 * (axis e, radius R: the cylinder's grown radius, or `grow`), (I - n n^T) / R
 * on a sphere or a box's rounded corner, 0 on a plane or a box's flat face.
 * Returns 1 where it is not 0. */
int rod_surface_curvature(const rod_surface *s, const double p[3], const double n[3], double grow,
                          double hessian[9]);

/* The geometry the rod's contact sees: an elastic pad's deformed surface
 * (the moving mesh of its surface faces, rod_surface.mesh) where it has
 * one, written into scratch as a mesh; else s itself. The other uses of a
 * pad (punctures, the needle's holes) keep its box. */
const rod_surface *rod_surface_contact_view(const rod_surface *s, rod_surface *scratch);

/* Checks a surface's inputs; returns 0, or -1 with a message that starts
 * with the scene key at fault ("size: ...") and says what is accepted.
 * Normalises `normal`. */
int rod_surface_check(rod_surface *s, char *err, size_t errlen);

/* The shape's scene word: "plane", "box", "cylinder", "sphere". */
const char *rod_surface_name(rod_surface_shape shape);

#endif
