/* shot.h: the camera a scene asks for, pure C: [render]'s camera keys
 * (look_at, follow, distance, fov, azimuth, elevation, eye) and the [shot]
 * sections, each a time range with its own camera; the shot at a time, and
 * the camera it makes from the one the framing gives (render.framing),
 * which supplies whatever the shot leaves out. */
#ifndef RODSIM_RENDER_SHOT_H
#define RODSIM_RENDER_SHOT_H

#include <stddef.h>

#include "base/ini.h"
#include "render/options.h"
#include "render/render_types.h"

/* Reads [render]'s camera keys into o->camera_keys (azimuth and elevation
 * also set o->view) and every [shot] into o->shots, sorted by start;
 * o->directed = 1 when any was given. 0, or -1 with a message naming
 * file:line, the key and what is accepted. */
int render_shots_read(ini_doc *doc, render_options *o, char *err, size_t errlen);

/* The shot of o at simulated time t: o->shots[k] when start <= t <= end
 * (where two shots meet, the later one), else &o->camera_keys. *index: k,
 * or -1 for camera_keys. */
const render_shot *render_shot_at(const render_options *o, double t, int *index);

/* The caption line at simulated time t: the shot's caption while a shot
 * that gives one lasts, else [render] caption ("" : none). Never NULL. */
const char *render_caption_at(const render_options *o, double t);

/* 1 when any caption line is drawn at some time ([render]'s or a shot's):
 * the overlay's band keeps room for it the whole run, so the framing does
 * not jump at a cut. */
int render_has_caption(const render_options *o);

/* The camera of shot s from `base` (the framing's camera of this frame, whose
 * projection kind, size in pixels, basis and scale fill in what s leaves
 * out); knot_centre (m, global; NULL: none found) is the point followed
 * with follow = knot; extent (m): the run's size, for the clip planes.
 * The point looked at lands at the picture's centre; its scale there is
 * fixed by distance and fov: 2 distance tan(fov / 2) metres over the
 * picture's height (orthographic too). */
void render_shot_camera(const render_shot *s, const render_camera *base,
                        const double knot_centre[3], double extent, render_camera *cam);

/* The camera of o at time t: the shot's, eased from the camera before it
 * over its ease time. base_at(t) is the framing's camera and knot centre at
 * time t (as render_shot_camera takes them). */
typedef void (*render_base_fn)(void *context, double t, render_camera *base,
                               double knot_centre[3], int *has_knot);
void render_directed_camera(const render_options *o, double t, render_base_fn base_at,
                            void *context, double extent, render_camera *cam);

#endif
