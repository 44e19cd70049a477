/* renderer.h: one view's renderer, internal to the render layer (render.c
 * drives one per view): what drawing a frame uses, made once (the camera,
 * the mesh, the grid, the overlay, the shadows, the GL target), and the
 * drawing of a frame: its meshes, the boxes of the picture they cover
 * drawn by GL and composited over the backdrop, then the overlay. */
#ifndef RODSIM_RENDER_RENDERER_H
#define RODSIM_RENDER_RENDERER_H

#include <stddef.h>

#include "render/camera.h"
#include "render/cutaway.h"
#include "render/edge_aa.h"
#include "render/follow.h"
#include "render/gl_render.h"
#include "render/glyphs.h"
#include "render/grid.h"
#include "render/image.h"
#include "render/mesh.h"
#include "render/options.h"
#include "render/overlay.h"
#include "render/shadow.h"
#include "render/surface.h"
#include "sim/recording.h"

/* Everything the frame loop of one view uses, made once. */
typedef struct renderer {
    const rod_recording *rec;
    const render_options *o;
    render_centreline line;      /* the drawn centreline of the frame being drawn */
    render_camera camera;
    double radius;
    arrow_scales arrows;
    render_mesh mesh;
    grid grid;
    render_overlay overlay;
    gl_renderer *gl;
    image *backdrop;             /* background and grid, drawn once */
    double pad;                  /* m, reach of the geometry around the points that carry it */
    int tiles_x, tiles_y;        /* tile grid over the picture, TILE pixels, from the bottom */
    unsigned char *tile_marked;  /* (tiles_y x tiles_x): TILE_DRAWN | TILE_SHADOW bits */
    int marking;                 /* the bit mark_points sets */
    int (*boxes)[4];             /* disjoint boxes over the marked tiles: x, y (down), w, h */
    int box_count;
    int (*drawn_boxes)[4];       /* the same over the tiles something is drawn in (not only a
                                    shadow falls): all GL draws when the receivers are cached */
    int drawn_box_count;
    rod_recording *view;         /* magnify != 1: frame 0 the run's first, 1 the drawn frame */
    double *values;              /* (nodes), the colour's quantity */
    float *colors;               /* (nodes x 3), linear 0..1; NULL: solid */
    double *previous;            /* (nodes x 3), m: the last frame given (speed) */
    double previous_time;        /* s */
    int have_previous;
    shadow_scene shadow;         /* surfaces, ground and shadows */
    int caster_indices;          /* this frame's triangles that cast (the punctures do not) */
    frame_band band;             /* the part of the picture the content may use */
    follow_path *follow;         /* framing follow or knot, or a directed camera (camera keys,
                                    shots): the camera's path; NULL: one camera for the run */
    render_camera fitted;        /* the run's camera (framing run), before any shot */
    int draws_overlay;           /* 1: the overlay is drawn here (not by a split frame) */
    strand_occlusion shading;    /* strands darkened where others pass near */
    edge_aa *edge_aa;            /* antialias fxaa: drawn at one sample, then the edges
                                    smoothed; NULL: multisampled or none */
    surface_mesh_topology *pads; /* (pad_slots) each elastic pad's triangle lists, by
                                    surface, made at the first frame; NULL: not yet */
    int pad_slots;
    cutaway_plane cut;           /* [render] cutaway: the tissue cut open along it (cut.on) */
    cutaway_scratch *cut_scratch; /* a cut elastic pad's cap, each frame; NULL: no cut */
} renderer;

/* Makes r for the run rec (its camera, grid and arrows from the whole of
 * it), the content kept inside `band` of the picture (the overlay's bands
 * kept free). 0, or -1 with a message (r freed). */
int renderer_create(renderer *r, const rod_recording *rec, const render_options *o,
                    const char *scene_name, const frame_band *band, char *err, size_t errlen);
void renderer_destroy(renderer *r);
/* Keeps frame `frame`'s positions for the next frame's speed (a frame not drawn). */
void renderer_remember(renderer *r, const rod_recording *rec, int frame);
/* Draws frame `frame` of rec (whose frame 0 is the run's first: the clamp
 * and the stripe's material direction come from it) into out. 0, or -1 on
 * a GL error. */
int renderer_draw(renderer *r, const rod_recording *rec, int frame, image *out);

#endif
