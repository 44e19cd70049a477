/* shadow.h: what takes the rod's shadow and the shadow map's light: the
 * receivers (the scene's surfaces, a ground plane, the wound) uploaded as
 * the static part of the picture, the catchers that tell which tiles a
 * shadow may darken, and the key light's map fitted to what the camera
 * shows. */
#ifndef RODSIM_RENDER_SHADOW_H
#define RODSIM_RENDER_SHADOW_H

#include <stddef.h>

#include "render/camera.h"
#include "render/cutaway.h"
#include "render/gl_render.h"
#include "render/options.h"
#include "sim/recording.h"

/* surfaces whose shadows are looked for (more are drawn, but cast no
 * shadow-marked tiles beyond these: a scene has a few) */
#define ROD_MAX_SURFACES_DRAWN 32
#define SHADOW_REACH 1e3      /* a shadow is followed this many motion sizes from its caster */

/* A half-space set n . p <= offset bounding where a receiver can take a
 * shadow (a slab about a plane, a box about a solid): the tiles a shadow
 * may darken are found by clipping the caster's shadow volume to it. */
typedef struct shadow_catcher {
    int count;
    double normal[6][3], offset[6];
    double stretch; /* a caster's pad grows this much on it (light at a slant) */
} shadow_catcher;

/* The receivers and the shadow map's light of one view (zeroed: none). */
typedef struct shadow_scene {
    int receivers;               /* 1: surfaces or a ground are drawn (boxes drawn whole) */
    int shadows;                 /* 1: the shadow map is drawn each frame */
    double key[3];               /* unit, towards the key light */
    double shadow_pad;           /* m: how far a shadow's soft edge reaches past its caster's */
    double lift;                 /* m: wound and punctures lie this far off their surface */
    double size;                 /* m: the motion's size (shadow reach) */
    shadow_catcher catchers[ROD_MAX_SURFACES_DRAWN + 1];
    int catcher_count;
    /* the shadow map's light (shadow_fit): its basis (e1, e2 across the
     * light, key along it), the casters' box in those coordinates over the
     * whole run, the map's size in texels and the thinnest caster (m) */
    double light_basis[3][3], light_lo[3], light_hi[3];
    int map_size;
    double thinnest;
} shadow_scene;

/* What shadow_receivers needs of the motion as drawn, taken before the
 * magnified copy is freed. */
typedef struct receiver_plan {
    int have_bounds;
    double lo[3], hi[3];  /* m: the casters over the whole run (padded) */
    int ground;
    double ground_point[3], ground_normal[3];
    double radius;        /* m: the tube's visual radius */
    double pad;           /* m: the geometry's reach around the points that carry it */
    double length;        /* m: the rod's */
    cutaway_plane cut;    /* the tissue cut open along it (cut.on; receiver_plan_make: none) */
} receiver_plan;

/* The ground plane a render draws (o->ground; render_recording's rule):
 * 1 with a point of it and its upward unit normal, 0 when none is drawn. */
int render_ground_plane(const rod_recording *rec, const render_options *o, double point[3],
                        double normal[3]);
/* The plan of the motion rec (as drawn) with a tube of `radius` (m). */
void receiver_plan_make(receiver_plan *p, const rod_recording *rec, const render_options *o,
                        double radius);
/* Clips the polygon (count points, up to 16) to the catcher (Sutherland-Hodgman);
 * returns the points left. */
int shadow_clip_polygon(double *poly, int count, const shadow_catcher *k);
/* rec's surfaces, the ground and the wound as static receivers (uploaded
 * to gl), the shadow catchers for the tiles, and with o->shadows the shadow
 * map's light fitted to cam; rec is the run as recorded (the plan may come
 * from its magnified copy). 0 (nothing to receive: s->receivers 0), or -1
 * with a message. */
int shadow_receivers(shadow_scene *s, gl_renderer *gl, const receiver_plan *plan,
                     const rod_recording *rec, const render_options *o,
                     const render_camera *cam, char *err, size_t errlen);
/* The shadow map's light, fitted to what the camera shows. Its box runs
 * along the light over all the casters (a caster out of the picture can
 * shadow what is in it), but across it only over the shadows that can be
 * seen: where the receivers (the surfaces, the ground, the rod's own box,
 * own_lo .. own_hi, m, or NULL: the casters' box over the whole run) lie
 * inside the camera's view, bounded by their convex sets' vertices there;
 * so a camera that follows a knot along a long thread keeps fine texels
 * (docs/decisions/0036-shadow-map-fit.md). Called at set-up and for
 * every frame of a camera that moves. 0, or -1 with a message. */
int shadow_fit(shadow_scene *s, gl_renderer *gl, const render_camera *cam, double radius,
               const double *own_lo, const double *own_hi, char *err, size_t errlen);

#endif
