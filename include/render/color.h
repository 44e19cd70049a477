/* color.h: what colours the tube along its length ([render] color): the
 * colour maps, the quantity each node of a frame shows and its range over
 * the run; the stripe's colour over them. */
#ifndef RODSIM_RENDER_COLOR_H
#define RODSIM_RENDER_COLOR_H

#include "render/options.h"
#include "sim/recording.h"

/* The colour map at f in 0..1 (clamped), sRGB bytes. */
void render_colormap_rgb(render_colormap map, double f, unsigned char rgb[3]);

/* The stripe's colour: amber over the solid tube, white over a colour map. */
const float *color_stripe(const render_options *o);

/* The colour's quantity at each node of `frame` into out (nodes): bending
 * curvature |(u1, u2)| from the director frames of neighbouring nodes
 * (Q_{k+1} = Q_k exp(ds_k u), ds_k segment k's rest length, rod_recording_segment:
 * a graded grid's own; the mean of the two segments beside a node);
 * twist u3 and tension N . d3 as recorded; speed |r - r_prev| / (t - t_prev), a backward
 * difference between drawn frames (0 for the first, previous = NULL). */
void color_values(const rod_recording *rec, int frame, render_color_mode mode,
                  const double *previous, double previous_time, double *out);

/* The colour bar's range, fixed for the video: o->color_range, or from the
 * extent's values (every frame it holds; a streamed run's sample): up to the
 * 99th percentile of |value| rounded up to 1, 2, 5 x 10^k (a spike at one
 * node for one frame would leave the rest of the run one dark colour; values
 * beyond clamp to the end colours and the bar says so), from 0 for the
 * magnitudes, symmetric for a signed twist. *clamped = 1 when some values
 * lie beyond. */
void color_range(const rod_recording *rec, const render_options *o, double *lo, double *hi,
                 int *clamped);

#endif
