/* follow.h: the follow camera ([render] framing follow or knot): the
 * framing of every frame of the run, smoothed in time, from which each
 * drawn frame's camera is taken. */
#ifndef RODSIM_RENDER_FOLLOW_H
#define RODSIM_RENDER_FOLLOW_H

#include "render/camera.h"
#include "render/glyphs.h"
#include "render/options.h"
#include "sim/geometry/proximity.h"
#include "sim/recording.h"

/* The framing of every frame of the extent recording, smoothed; the camera
 * of a frame drawn is interpolated from it in time. */
typedef struct follow_path {
    int count;           /* samples: the extent's frames */
    double *time;        /* (count), s */
    double *centre;      /* (count x 3), m: in the camera basis (right, up, back) */
    double *extent;      /* (count), m: orthographic half height, or perspective eye distance */
    point_cloud frame;   /* one frame's points, scratch sized at create */
    double depth, size;  /* m: the run's depth along the view and its largest size (clip planes) */
    int floor;           /* a floor (plane or ground) is drawn: the orthographic eye stands back */
    frame_band band;
    render_camera basis; /* the run's camera: size, projection kind and basis */
    int knot_framing;    /* framing knot: the knotted part is framed */
    double *knot_centre; /* (count x 3), m, global: the knotted part's centre, smoothed
                            (follow = knot); NULL: not asked */
    /* framing knot or follow = knot: the broad phase and its pairs (NULL: neither) */
    rod_proximity *prox;
    rod_segment_pair *pairs;
    int max_pairs;
} follow_path;

/* The follow path over the extent's frames (rec: the motion as drawn), from
 * the run's camera (its size, projection and basis) and the band the
 * content may use; floor: a floor is drawn (an orthographic eye stands
 * back). NULL when out of memory. */
follow_path *follow_create(const rod_recording *rec, const render_options *o,
                           const arrow_scales *arrows, double radius,
                           const render_camera *run_camera, const frame_band *band,
                           int floor);
void follow_destroy(follow_path *fp);
/* The knotted part's centre (m, global) at time t, interpolated between
 * the path's frames. 0, or -1 when the path has no knot centres. */
int follow_knot_centre(const follow_path *fp, double t, double centre[3]);
/* The camera of frame `frame` of rec (the motion as drawn) at time t: the
 * path's framing at t, widened where it would cut this frame's rod. */
void follow_camera(follow_path *fp, const rod_recording *rec, const render_options *o,
                   const arrow_scales *arrows, int frame, double t, render_camera *cam);

#endif
