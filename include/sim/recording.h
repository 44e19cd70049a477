/* recording.h: the frames of a run, as plain arrays, handed from the
 * simulation to the writers (CSV, renderer). The renderer sees only this:
 * centreline points, director frames, the twist, time and loads, and what
 * it draws of the scene (the ends' holders, the needle, the distributed
 * load, the obstacles); nothing of the model or a scheme's internals.
 * Frames are appended at the output rate while the run goes; the renderer
 * reads them after the run completes, so a diverged run writes nothing,
 * and the camera can frame the whole motion. The CSV does not need them:
 * it is written frame by frame from the state. */
#ifndef RODSIM_RECORDING_H
#define RODSIM_RECORDING_H

#include <stddef.h>

#include "sim/rod_types.h"

/* The most punctures a frame holds (the run's). */
#define RECORDING_MAX_PUNCTURES ROD_MAX_PUNCTURES

/* What holds an end, as drawn: the model's end kind in the renderer's
 * words (the renderer does not see the model). */
typedef enum {
    RECORDING_END_CLAMPED = 0, /* position and frame held: a block oriented with the end's frame */
    RECORDING_END_PINNED,      /* position held, free to rotate: a ball */
    RECORDING_END_FREE         /* nothing held: nothing drawn */
} recording_end_kind;

typedef struct recording_end {
    recording_end_kind kind;
    int driven;                /* 1: the end follows a path (named in the overlay) */
    int sliding;               /* 1: on a slide (a sleeve), 2: on a slide without turning
                                  about it (a carriage; ends.*_twist = held); 0: neither */
} recording_end;

/* An obstacle of the scene, as drawn (the model's [surface], copied). */
typedef enum {
    RECORDING_SURFACE_PLANE = 0, /* the half-space below `normal` through `center` */
    RECORDING_SURFACE_BOX,       /* axis-aligned, edges size[0..2] along x y z, centred on center */
    RECORDING_SURFACE_CYLINDER,  /* radius size[0] about the axis through center along `normal`,
                                    unbounded along it */
    RECORDING_SURFACE_SPHERE,    /* radius size[0] about center */
    RECORDING_SURFACE_MESH       /* triangles (mesh_vertices, mesh_triangles) */
} recording_surface_shape;

typedef struct recording_surface {
    recording_surface_shape shape;
    double center[3];          /* m, global */
    double normal[3];          /* unit: the plane's outward normal, the cylinder's axis */
    double size[3];            /* m: the box's edge lengths; size[0] the cylinder's or
                                  sphere's radius */
    double rounding;           /* m: a box's edges and corners rounded to this radius (0: sharp) */
    int tissue;                /* 1: skin (a needle passing through it makes punctures) */
    int mesh_vertex_count, mesh_triangle_count; /* a mesh's; 0 for other shapes */
    double *mesh_vertices;     /* (mesh_vertex_count x 3), m, global; owned by the recording */
    int *mesh_triangles;       /* (mesh_triangle_count x 3) vertex indices, counter-clockwise
                                  seen from outside; owned by the recording */
    /* an elastic pad (a box with model = elastic), drawn deformed: its surface, the
     * boundary faces of its tets (faces of exactly one tet; the wound's slit walls
     * among them), and its surface nodes' positions each frame; 0 / NULL otherwise */
    int pad_node_count, pad_triangle_count;
    int *pad_nodes;            /* (pad_node_count) the solid's node of each surface node */
    int *pad_triangles;        /* (pad_triangle_count x 3) surface node indices, counter-
                                  clockwise seen from outside (at rest) */
    double *pad_positions;     /* (frames x pad_node_count x 3), m, global; owned */
} recording_surface;

/* Copies a mesh surface's vertices and triangles into to (from's, or a
 * zeroed surface): 0, or -1 when out of memory. */
int recording_surface_copy_mesh(recording_surface *to, const recording_surface *from);

/* A surgical instrument, as drawn (the model's [instrument]): its kind and
 * dimensions, fixed; its pose and opening are per frame. Local frame: x
 * along the shafts toward the jaws' tip (the origin), z the jaws' opening
 * plane with x; each jaw turns about its hinge at (-hinge, 0, +-jaw_radius). */
typedef enum {
    RECORDING_NEEDLE_HOLDER = 0, /* short jaws, a box lock, crossed shanks, ring handles */
    RECORDING_FORCEPS,           /* two tines sprung from their back end */
    RECORDING_SCISSORS           /* long blades, a screw, crossed shanks, ring handles */
} recording_instrument_kind;

typedef struct recording_instrument {
    recording_instrument_kind kind;
    double size;              /* m: overall length */
    double hinge;             /* m: from the tip back to where the jaws turn */
    double jaw_length;        /* m: the gripping part at the front */
    double jaw_radius;        /* m */
    double shank_radius;      /* m */
    double lock_radius;       /* m: the box lock's capsule (0: none), across the hinge */
    double lock_half_span;    /* m: its segment from local z = -this to +this */
} recording_instrument;

/* Numbers a frame records per instrument: position (3, m), rotation (9,
 * row-major, local to global), each jaw's turn from the axis (1, rad). */
#define RECORDING_INSTRUMENT_NUMBERS 13

/* The most rods a joined recording holds (rod_recording_join) */
#define RECORDING_MAX_RODS 8

typedef struct rod_recording {
    /* fixed for the run */
    int nodes;
    /* several rods (rod_recording_join): rod k is nodes rod_first[k] ..
     * rod_first[k + 1] - 1, each drawn as its own tube with its own ends
     * (rod_end[k]); 0: one rod, all the nodes */
    int rod_count;
    int rod_first[RECORDING_MAX_RODS + 1];
    recording_end rod_end[RECORDING_MAX_RODS][2];
    double length;        /* m */
    double ds;            /* m, node spacing of a uniform grid (L / (NS - 1)) */
    double *arc;          /* (nodes), m, owned: each node's arc length from its rod's root
                             on a graded grid (rod.refine; a joined recording: each rod's
                             from its own root); NULL: uniform, node i at i ds
                             (rod_recording_arc) */
    double diameter;      /* m, true diameter */
    int self_contact;     /* 1: strands touched in a frame appended (the renderer then draws
                             the true radius, so that touching strands look touching) */
    char scheme[16];      /* "thesis", "implicit", "static" */
    char scene[128];      /* scene name (file base name) */
    recording_end ends[2]; /* [0] the root (s = 0), [1] the tip (s = L) */
    double needle_radius; /* m; > 0: a curved needle whose back is at the tip, drawn instead
                             of the tip's block or ball (scene [ends] needle) */
    double distributed_force[3]; /* N/m, global: the weight and distributed force (drawn as
                                    an arrow when not 0; "down" for the ground) */
    int surface_count;
    recording_surface *surfaces; /* (surface_count), owned; NULL with surface_count 0: none */
    int instrument_count;        /* 0 .. ROD_MAX_INSTRUMENTS */
    recording_instrument instruments[ROD_MAX_INSTRUMENTS];

    /* frames */
    int frame_count;
    int capacity;
    double *time;         /* (frames), s */
    double *position;     /* (frames x nodes x 3), m, global */
    double *frame;        /* (frames x nodes x 9), row-major Q, columns d1 d2 d3 (global) */
    double *twist;        /* (frames x nodes), u3 at each node, 1/m (for the (4.17) stripe) */
    double *tension;      /* (frames x nodes), N . d3 at each node, N (colour by tension) */
    double *tip_force;    /* (frames x 3), N, global components */
    double *tip_moment;   /* (frames x 3), N m, global components */
    int *puncture_count;  /* (frames), punctures the thread passes through
                             (0..RECORDING_MAX_PUNCTURES) */
    double *puncture;     /* (frames x RECORDING_MAX_PUNCTURES x 3), m, global: their points;
                             a recording made by hand may leave both NULL: none */
    double *instrument_pose; /* (frames x instrument_count x RECORDING_INSTRUMENT_NUMBERS);
                             NULL without instruments */
    double peak_force;    /* N, the largest |tip force| of every frame appended or noted */
    double peak_moment;   /* N m, the same for the tip moment */
    double *force_scratch; /* (nodes x 3) the internal force while appending */
    double needle_frame0[9]; /* a pinned tip's frame at the first frame (its needle's turn
                                is recorded from it: rod_recording_append) */
} rod_recording;

/* Node `node`'s arc length from its rod's root, m: i ds on a uniform grid. */
static inline double rod_recording_arc(const rod_recording *r, int node)
{
    return r->arc ? r->arc[node] : node * r->ds;
}
/* Segment k's (node k to k + 1) rest length, m: ds on a uniform grid. */
static inline double rod_recording_segment(const rod_recording *r, int k)
{
    return r->arc ? r->arc[k + 1] - r->arc[k] : r->ds;
}
/* The longest segment, m (ds on a uniform grid). */
double rod_recording_longest_segment(const rod_recording *r);
/* Gives r its own copy of `arc` (r->nodes of them; NULL: a uniform grid,
 * r->arc freed). 0, or -1 when out of memory (r->arc then NULL). */
int rod_recording_set_arc(rod_recording *r, const double *arc);

/* Instrument k's pose in `frame`: its RECORDING_INSTRUMENT_NUMBERS numbers,
 * or NULL when the recording has none. */
const double *rod_recording_instrument(const rod_recording *r, int frame, int k);
/* Surface k's pad node positions at `frame` (pad_node_count x 3, m), or
 * NULL when it is no elastic pad or the frame is out of range. */
const double *rod_recording_pad_positions(const rod_recording *r, int k, int frame);
/* Bytes a recording of the model holds for `frames` frames: rod_recording_bytes
 * and its elastic pads' positions (every solid node counted: a bound). */
double rod_recording_model_bytes(const rod_model *m, double frames);

/* Room for `capacity` frames (grows when exceeded), with what the picture
 * needs of the model (its ends, needle, distributed force and surfaces,
 * copied). NULL when out of memory. */
rod_recording *rod_recording_create(const rod_model *m, const char *scene, int capacity);
void rod_recording_destroy(rod_recording *r);
/* u3 at node `node` of the state, 1/m (staggered schemes: the mean of the
 * midpoints beside it), as the recording and the CSV hold it. */
double rod_recording_node_twist(const rod_state *s, int node);
/* Bytes a recording of `frames` frames of `nodes` nodes holds (112 per node
 * per frame; 56 per frame for time and loads, 4 + 24 RECORDING_MAX_PUNCTURES for
 * the punctures): what a run must fit in memory to frame its video. */
double rod_recording_bytes(int nodes, double frames);
/* The tip load at s->time from the model, global components: force (N) and
 * moment (N m). */
void rod_recording_tip_load(const rod_model *m, const rod_state *s, double force[3],
                            double moment[3]);
/* Takes the tip load of a frame that is not kept into the peaks. */
void rod_recording_note_peaks(rod_recording *r, const rod_model *m, const rod_state *s);
/* The punctures of frame `frame`: their count, points into *points
 * (count x 3, m); 0 when the recording keeps none. */
int rod_recording_punctures(const rod_recording *r, int frame, const double **points);
/* Keeps frames 0, 2, 4, ... (and the peaks): halves a sampled recording. */
void rod_recording_halve(rod_recording *r);
/* One recording of several rods recorded side by side (parts: count, 2 ..
 * RECORDING_MAX_RODS, each with the same frames): their nodes one after
 * another in each frame, rod_count and rod_first set; the scene (surfaces,
 * loads, scheme, instruments) is the first part's, whose surfaces and
 * instruments' poses move into the joined one. NULL when out of memory or the parts differ in frames. */
rod_recording *rod_recording_join(rod_recording *const *parts, int count);

/* The thread left in frame `frame` among nodes lo .. hi - 1 (one rod of
 * the recording: 0 .. nodes, or rod_first[k] .. rod_first[k + 1]): after a
 * cut, rod_recording_append puts the nodes cut away on the cut end, each an
 * exact copy of its position and frame (no two nodes of a thread coincide
 * otherwise). Returns how many nodes are left, the first of them in *first;
 * hi - lo and lo when nothing was cut. */
int rod_recording_kept(const rod_recording *r, int frame, int lo, int hi, int *first);

/* Appends the state as a frame; the tip load at s->time comes from the model.
 * A state of a cut thread (sim/cut.h; m its model) fills its nodes of the
 * recording's and puts the ones cut away at the cut end. Returns 0, or -1
 * when out of memory. */
int rod_recording_append(rod_recording *r, const rod_model *m, const rod_state *s);

#endif
