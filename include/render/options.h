/* options.h: the renderer's options, the scene's [render] section: what is
 * drawn and how (render_options), their defaults and their reading. */
#ifndef RODSIM_RENDER_OPTIONS_H
#define RODSIM_RENDER_OPTIONS_H

#include <stddef.h>

#include "base/ini.h"
#include "render/render_types.h"
#include "sim/recording.h"

typedef enum {
    RENDER_STRIPE_DIRECTOR = 0, /* the material line from the director frames: exact for any shape */
    RENDER_STRIPE_FORMULA,      /* thesis (4.17) literally: a rotation about x by s u3 */
    RENDER_STRIPE_OFF
} render_stripe_mode;

typedef enum { RENDER_CAMERA_PERSPECTIVE = 0, RENDER_CAMERA_ORTHOGRAPHIC } render_camera_kind;

/* How the camera frames the motion ([render] framing). */
typedef enum {
    RENDER_FRAMING_RUN = 0, /* one camera for the whole run: every frame's rod, glyphs, arrows */
    RENDER_FRAMING_FOLLOW,  /* per frame: the rod's current bounds centred and filling the
                               picture, smoothed over time (never clipped) */
    RENDER_FRAMING_KNOT     /* as follow, around the knotted part only (the strands within
                               3 diameters of a far strand, 3 diameters of arc beyond):
                               the tails leave the picture; the whole rod while none is near */
} render_framing;

/* One view of a frame split into side-by-side tiles ([render] views). */
typedef enum {
    RENDER_VIEW_PERSPECTIVE = 0, /* along render.view, perspective */
    RENDER_VIEW_ORTHOGRAPHIC,    /* along render.view, orthographic */
    RENDER_VIEW_TOP,             /* orthographic, looking down z: x right, y up */
    RENDER_VIEW_FRONT,           /* orthographic, looking along +y: x right, z up */
    RENDER_VIEW_SIDE             /* orthographic, looking along -x: y right, z up */
} render_view_kind;
#define RENDER_MAX_VIEWS 3

/* What colours the tube along its length ([render] color). */
typedef enum {
    RENDER_COLOR_SOLID = 0, /* one colour (render_rod_color) */
    RENDER_COLOR_CURVATURE, /* bending curvature sqrt(u1^2 + u2^2), 1/m */
    RENDER_COLOR_TWIST,     /* u3, 1/m */
    RENDER_COLOR_TENSION,   /* N . d3, N: the internal force along the rod, as recorded */
    RENDER_COLOR_SPEED      /* |v|, m/s, by finite difference between drawn frames */
} render_color_mode;

/* Perceptually uniform colour maps (never jet). */
typedef enum { RENDER_MAP_VIRIDIS = 0, RENDER_MAP_CIVIDIS } render_colormap;

/* Overlay items ([render] hide lists those not drawn); all shown by default. */
enum {
    RENDER_SHOW_TITLE = 1 << 0,    /* the scene's title */
    RENDER_SHOW_CAPTION = 1 << 1,  /* [render] caption, when given */
    RENDER_SHOW_TIME = 1 << 2,     /* t, scheme, nodes */
    RENDER_SHOW_ENDS = 1 << 3,     /* what holds the ends, the needle */
    RENDER_SHOW_LEGEND = 1 << 4,   /* top right: radius exaggeration, magnification, speed, stripe */
    RENDER_SHOW_LOADS = 1 << 5,    /* bottom left: tip force and moment (hidden when zero) */
    RENDER_SHOW_SCALE = 1 << 6,    /* scale bar (with the grid) */
    RENDER_SHOW_TRIAD = 1 << 7,    /* x y z axes, turning with the camera */
    RENDER_SHOW_GRAVITY = 1 << 8,  /* the distributed load's direction, when not zero */
    RENDER_SHOW_COLORBAR = 1 << 9, /* the colour bar (color other than solid) */
    RENDER_SHOW_ALL = (1 << 10) - 1
};

/* Whether a ground plane (with the rod's shadow) is drawn ([render] ground). */
typedef enum {
    RENDER_GROUND_AUTO = 0, /* when a distributed load (gravity) acts, no plane surface exists
                               and the camera looks at the ground from above */
    RENDER_GROUND_YES,      /* whenever a distributed load gives "down" (else as no) */
    RENDER_GROUND_NO
} render_ground_mode;

/* The tissue cut open along a plane ([render] cutaway), as a textbook draws
 * a stitch in section: the tissue on the normal's side is not drawn, its
 * cut face is (render/cutaway.h). */
typedef enum {
    RENDER_CUTAWAY_NO = 0,
    RENDER_CUTAWAY_STITCH, /* yes: the plane through the stitch's punctures, facing the eye */
    RENDER_CUTAWAY_PLANE   /* x0 y0 z0 nx ny nz: render_options.cutaway_plane */
} render_cutaway_mode;

/* Whether the overlay names the knot type of the centreline ([render]
 * knot): top right, per frame, e.g. "knot: trefoil (3_1), right-handed". */
typedef enum {
    RENDER_KNOT_AUTO = 0, /* when a frame of the run is knotted (render_knot_shown) */
    RENDER_KNOT_YES,
    RENDER_KNOT_NO
} render_knot_mode;

/* How a frame is antialiased ([render] antialias), when
 * render.samples > 0 (0: not at all). */
typedef enum {
    RENDER_AA_MSAA = 0, /* multisampling with `samples` samples */
    RENDER_AA_FXAA      /* (default) one sample per pixel, then FXAA over what the
                           frame drew (edge_aa.h); the backdrop still multisampled */
} render_antialias;

/* A camera asked for by the scene: [render]'s camera keys (the whole run)
 * or a [shot]'s (a time range). What is not given comes from the camera
 * the framing makes (render.framing), so a shot may change only one thing. */
#define RENDER_MAX_SHOTS 16
typedef struct render_shot {
    double start, end;     /* s, simulated: the shot covers start <= t <= end (where two
                              meet, the later one; [render]: all) */
    double ease;           /* s, simulated: the camera moves from the one before over this
                              time from start (smoothstep); 0: a cut */
    int has_look_at;
    double look_at[3];     /* m, global: the point at the picture's centre */
    int follow_knot;       /* 1: the centre of the knotted part instead (per frame, smoothed) */
    double distance;       /* m, from the eye to the point looked at; 0: the framing's scale */
    double fov;            /* deg, perspective vertical field of view; 0: the default 30 */
    int has_view;
    double view[3];        /* direction from the point looked at to the eye (from azimuth
                              and elevation; a shot's missing angle from render.view) */
    int has_eye;
    double eye[3];         /* m, global: where the eye stands (sets view and distance) */
    char caption[256];     /* [shot] caption: the caption line while the shot lasts (over
                              [render] caption); "": [render]'s */
} render_shot;

/* A time range played slower ([render] slow_motion = T0 T1 FACTOR). */
#define RENDER_MAX_SLOW 8
typedef struct render_slow {
    double start, end; /* s, simulated */
    double factor;     /* > 1: frames this many times closer in simulated time */
} render_slow;

/* Scene [render] section; render_options_default() makes a good picture. */
typedef struct render_options {
    int width, height;           /* pixels (even: yuv420p) */
    int fps;                     /* video frames per second */
    int crf;                     /* H.264 quality 0 (lossless) .. 51 (worst); 18 looks clean */
    char preset[16];             /* x264 speed preset: ultrafast .. veryslow */
    int samples;                 /* multisample antialiasing, 0 = off */
    render_antialias antialias;  /* fxaa (default; samples for the backdrop) or msaa */
    double visual_radius;        /* m; <= 0: auto, 1% of the length (never below true radius) */
    int sides;                   /* tube cross-section polygon, 6..128 */
    render_stripe_mode stripe;
    int arrows;                  /* tip force and moment arrows */
    render_camera_kind camera;
    double view[3];              /* direction from the target to the eye (any length) */
    unsigned char background[3]; /* sRGB */
    int grid;                    /* backdrop grid and scale bar */
    int overlay;                 /* text: scene, time, scheme, loads */
    int frames_png;              /* also write every frame as PNG */
    double needle_arc;           /* the needle's arc (its radius: rod_recording), fraction of
                                    a circle: 0.375 (3/8, default) or 0.5 (1/2) ([render]
                                    needle_arc) */
    int poster;                  /* write the last frame as <scene>.png */
    char title[256];             /* overlay title; "" (default): the scene's name */
    int title_auto;              /* 1: title holds the scene's own words (render_title_from_text),
                                    cut to the picture's width when drawn */
    char caption[256];           /* a line under the title; "" (default): none */
    unsigned show;               /* RENDER_SHOW_* items drawn when overlay is on */
    render_color_mode color;     /* what colours the tube (default solid) */
    float rod_color[3];          /* linear 0..1, the solid tube (default render_rod_color) */
    render_colormap colormap;    /* viridis (default) or cividis */
    double color_range[2];       /* lo, hi in the quantity's unit; lo == hi (default): the
                                    range over the whole run, fixed for the video */
    double speed;                /* playback: simulated seconds per video second (1: real
                                    time, 0.25: 4x slow motion, 10: time-lapse) */
    double magnify;              /* displacements from the first frame drawn x this (1: none) */
    int smooth;                  /* 1 (default): the tube through a smooth curve between the
                                    nodes (mesh.c: centreline_rings); 0: straight between */
    int shadows;                 /* 1 (default): the rod, needle, end glyphs and arrows cast
                                    shadows from the key light on the surfaces, the ground and
                                    each other (a shadow map) */
    render_ground_mode ground;   /* a ground plane below the whole run's lowest point */
    int wound;                   /* 1: wound_line is drawn (a dark red incision) */
    double wound_line[6];        /* m, global: the wound's two ends x1 y1 z1 x2 y2 z2 */
    render_cutaway_mode cutaway; /* the tissue cut open along a plane (cutaway.h); default no */
    double cutaway_plane[6];     /* RENDER_CUTAWAY_PLANE: a point (m, global) and a normal
                                    towards the side not drawn (any length) */
    render_knot_mode knot;       /* the knot type in the overlay: auto (default), yes, no */
    render_framing framing;      /* run (default), follow or knot */
    int view_count;              /* 0 (default): one view (camera, view); 2 .. RENDER_MAX_VIEWS:
                                    the frame split into that many tiles, left to right */
    render_view_kind views[RENDER_MAX_VIEWS];
    int overlay_solver;          /* 1 (default): the time line names the scheme and nodes */
    int directed;                /* 1: camera keys or shots given (the camera is rebuilt per
                                    frame from camera_keys and shots) */
    render_shot camera_keys;     /* [render]'s camera keys, the camera outside every shot */
    int shot_count;
    render_shot shots[RENDER_MAX_SHOTS]; /* [shot] sections, by start time, not overlapping;
                                    each starts from camera_keys */
    int slow_count;
    render_slow slow[RENDER_MAX_SLOW]; /* by start time, not overlapping */
    double slow_auto;            /* > 1 (slow_motion = auto [FACTOR]): this factor around the
                                    knot's fastest tightening, found by a first pass of the run
                                    (frame_schedule.h); 0: not asked */
    struct render_timing *timing; /* NULL (default): not measured; else filled (make bench) */
    struct render_camera *cameras; /* NULL (default); else each drawn frame's camera of each
                                    view (frame x max(view_count, 1) + view), for the tests */
    int camera_capacity;         /* entries in cameras; frames beyond it are not reported */
} render_options;

/* Where render_recording's time went (seconds summed over the frames), for
 * the benchmark. The drawing thread (mesh .. overlay) and the writing thread
 * (convert .. png) run at the same time, so the parts add up to more than
 * the wall time when the overlap works. */
typedef struct render_timing {
    double mesh;      /* tube, stripe, clamp, arrow triangles and the tile boxes */
    double gl;        /* upload, clear, draw, resolve, read back (llvmpipe), shadow included */
    double shadow;    /* the shadow map's depth pass (part of gl) */
    double composite; /* backdrop copy and the boxes blended over it */
    double overlay;   /* text */
    double wait;      /* drawing thread waiting for a free queue slot */
    double convert;   /* RGB to yuv420p */
    double encode;    /* x264 and the MP4 muxer */
    double png;       /* PNG frames */
    double wall;      /* the whole call */
    int frames;
} render_timing;

void render_options_default(render_options *o);
/* Reads [render] (all keys optional) over the defaults. 0, or -1 with a
 * message naming file:line, the key and what is accepted. */
int render_options_read(ini_doc *doc, render_options *o, char *err, size_t errlen);

/* Frames per simulated second a run records for a video at o->fps that
 * plays at o->speed: round(fps / speed), at least 1 (each recorded frame is
 * one video frame). */
int render_output_rate(const render_options *o);

/* The slow-motion factor at simulated time t (1: none). */
double render_slow_factor(const render_options *o, double t);

/* The overlay title a scene file's own words give: its first comment
 * paragraph's first sentence (the text after '#' of the comment lines that
 * open the file, up to a blank comment line), shortened to at most `outlen`
 * - 1 and RENDER_TITLE_WORDS characters at a ": " or ", " or a word; ""
 * when the file opens with no comment. */
#define RENDER_TITLE_WORDS 72
void render_title_from_text(const char *text, char *out, size_t outlen);

/* The camera and direction (from the rod to the eye) of a view; scene_view
 * is render.view (may alias view). */
void options_view_camera(render_view_kind kind, const double scene_view[3],
                         render_camera_kind *camera, double view[3]);

#endif
