/* rod_types.h: the plain types of the Cosserat rod: the model (fixed for a
 * run), its state (changes every step), loads, ends, obstacles, the options
 * and the report of a step. The bottom of the sim floor: every sim module
 * that needs these types includes this header, and rod.h declares the
 * functions of rod.c on them.
 *
 * Units are SI throughout. Equations are cited from the thesis (Nuti, 2014).
 *
 * Conventions (thesis section 4.2):
 *   - node i = 0 is the clamped end (s = 0), node NS-1 the free end (s = L);
 *   - the rod starts straight along +x with d3 = +x, d1 = +y, d2 = +z;
 *   - every vector in the state except position and frame is stored in
 *     director components (on d1, d2, d3), as the thesis writes them.
 *
 * The simulation layer knows nothing of OpenGL, PNG or video.
 */
#ifndef RODSIM_ROD_TYPES_H
#define RODSIM_ROD_TYPES_H

#include <stddef.h>

typedef enum {
    ROD_SCHEME_THESIS = 0, /* chapter 4 as written: forward Euler, central differences */
    ROD_SCHEME_IMPLICIT,   /* theta-method (backward Euler / Crank-Nicolson), Newton */
    ROD_SCHEME_STATIC,     /* equilibrium under the load at each output time */
    ROD_SCHEME_COUNT
} rod_scheme_kind;

typedef enum {
    ROD_FRAME_DIRECTOR = 0, /* components on d1 d2 d3 of the tip: a follower load (thesis 4.2) */
    ROD_FRAME_GLOBAL        /* components on x y z: a dead load */
} rod_load_frame;

typedef enum {
    ROD_PROFILE_STEP = 0, /* full load from t = 0 */
    ROD_PROFILE_RAMP,     /* linear from 0 at t = 0 to full at t = t1, then held */
    ROD_PROFILE_PULSE,    /* full load for t1 <= t < t2, zero otherwise */
    ROD_PROFILE_IMPULSE,  /* thesis fig. 10: +load for 0 <= t < t1, -load for t1 <= t < 2 t1 */
    ROD_PROFILE_TABLE     /* piecewise linear from a CSV table, held after its last row */
} rod_profile_kind;

/* End conditions, the same words at either end. The root is at
 * s = 0, the tip at s = L. A held end stays where it starts, or follows its
 * path (rod_model root_motion / tip_motion), or slides freely along its
 * `slide` direction (a sleeve: Euler's and Greenhill's columns use
 * tip_slide = 1 0 0); the force and moment that hold it are reported in
 * rod_state end_force / end_moment.
 * A scheme that does not model a combination refuses it at create with a
 * message naming the end and what it supports (rod_model_require_*). */
typedef enum {
    ROD_END_CLAMPED = 0, /* position and frame held (or driven); a clamped tip that slides
                            keeps d3 along its slide direction and is free to twist about it */
    ROD_END_PINNED,      /* position held (or driven), free to rotate (a ball joint); a pinned
                            root also holds the twist about d3 (a torsion stop), so the rod has
                            no free rotation about its own axis */
    ROD_END_FREE         /* nothing held; at the tip the tip loads act */
} rod_end_kind;

/* A driven end's path: the held end's position (and, for a clamped end, its
 * rotation from its initial frame) as a function of time, from a table
 * t,x,y,z[,rx,ry,rz] (scene [ends] root_motion / tip_motion). Opaque: made
 * and evaluated by sim/path.h. */
typedef struct rod_path rod_path;

/* A concentrated load at one node (scene [point_load], repeatable): dead
 * (global components), scaled by the tip's time profile factor (a 2-column
 * table or step/ramp/pulse; a 7-column table drives only the tip). */
typedef struct rod_point_load {
    int node;          /* 0..NS-1, the node nearest the scene's arc length s */
    double force[3];   /* N, global x y z */
    double moment[3];  /* N m, global x y z */
} rod_point_load;

/* A rigid obstacle the rod touches (scene [surface], repeatable).
 * The rod touches it at its physical radius; contact and Coulomb friction
 * are solved by the implicit scheme (sim/surface.h has the geometry). */
typedef enum {
    ROD_SURFACE_PLANE = 0, /* the half-space below `normal` through `center` is solid */
    ROD_SURFACE_BOX,       /* axis-aligned, edges size[0..2] along x y z, centred on center */
    ROD_SURFACE_CYLINDER,  /* radius size[0] about the axis through center along `normal`;
                              unbounded along its axis (a spool, a vessel, a capstan) */
    ROD_SURFACE_SPHERE,    /* radius size[0] about center */
    ROD_SURFACE_MESH       /* a fixed triangle mesh (an STL file), moved by center */
} rod_surface_shape;

struct rod_mesh; /* sim/contact/mesh.h */

typedef struct rod_surface {
    rod_surface_shape shape;
    double center[3];  /* m, global */
    double normal[3];  /* unit: the plane's outward normal, the cylinder's axis */
    double size[3];    /* m: the box's edge lengths; size[0] the cylinder's, sphere's radius */
    double friction;   /* Coulomb coefficient mu >= 0 between the rod and the surface */
    int tissue;        /* 1: a needle passing through it makes punctures */
    double track_spacing; /* m: > 0, the needle's path inside the tissue leaves punctures
                             this far apart along the thread (at least two node spacings),
                             so the thread lies in the needle's track; 0 (default): only
                             where it enters and leaves */
    double rounding;   /* m: a box's edges and corners rounded to this radius (0: sharp) */
    int line;          /* the scene line of its [surface] header (messages); 0: none */
    struct rod_mesh *mesh; /* shape mesh: its triangles, owned by the model (released with
                              it); NULL otherwise */
    struct tissue_solid *solid; /* box with model = elastic: the deformable pad (its state:
                              positions and loads, stepped with the rod), owned by the model
                              (released with it); NULL: rigid */
    int solid_shared;  /* 1: solid is another rod's of the scene (several rods share one
                          pad: sim/rod_set.h): not released with this model, and stepped by
                          the set, not by this rod's step */
} rod_surface;

/* A puncture given in the scene ([puncture], repeatable): a point the
 * centreline must pass through, at whatever arc length is there, the thread
 * sliding through it with Coulomb friction. */
typedef struct rod_puncture {
    double point[3];   /* m, global */
    double friction;   /* Coulomb coefficient along the thread, >= 0 */
    int index;         /* its [puncture] instance in the scene (messages; with several rods
                          a rod holds only those naming it) */
} rod_puncture;

/* The most punctures a run holds (given plus made by the needle). */
#define ROD_MAX_PUNCTURES 16
/* The most material points a puncture in an elastic pad bears on. */
#define ROD_PATCH_NODES 512

/* Surgical instruments (scene [instrument], sim/instrument.h): rigid tools
 * driven along a path of poses of their jaws' tip, whose capsules the thread
 * touches and whose closed jaws grasp it. */
typedef enum {
    ROD_INSTRUMENT_NEEDLE_HOLDER = 0,
    ROD_INSTRUMENT_FORCEPS,
    ROD_INSTRUMENT_SCISSORS
} rod_instrument_kind;

#define ROD_MAX_INSTRUMENTS 4

typedef struct rod_instrument {
    rod_instrument_kind kind;
    char name[32];
    rod_path *pose;    /* owned: t,x,y,z,rx,ry,rz: the jaws' tip (m, global) and the rotation
                          from the global axes (local x: along the shafts toward the tip,
                          local z: the jaws' opening plane with x) */
    rod_path *jaw;     /* owned: t, opening (0 closed .. 1 open), 0, 0 */
    double size;       /* m: overall length */
    double friction;   /* Coulomb coefficient of the thread on the instrument */
    double grip;       /* N: the force along the thread beyond which it slides through
                          closed jaws */
    int needle;        /* 1: holds the needle: the path drives the thread's tip */
    double max_depth;  /* m: the deepest its path may take the jaws into a rigid surface
                          (sim/instrument_path.h); 0: the jaws' thickness */
    char rod[32];      /* rod = NAME: the only rod its jaws take ("": the nearest of any) */
    int grasp_off;     /* 1: its jaws never take this model's rod (rod = another rod's
                          name); they still touch it */
    int line;          /* the scene line of its [instrument] header (messages); 0: none */
    int may_overlap;   /* 1: its path may take it through another instrument (allowed,
                          not refused: sim/instrument_overlap.h) */
    char path_name[96]; /* its path key's value as the scene gives it (messages); "": none */
} rod_instrument;

/* The needle handed to an instrument's jaws (scene [needle_grasp],
 * sim/needle_grasp.h): from time t they hold it as it was at t. */
#define ROD_MAX_NEEDLE_GRASPS 8
typedef struct rod_needle_grasp {
    double t;          /* s */
    int instrument;    /* index in the model's instruments */
    int line;          /* the scene line of its [needle_grasp] header (messages) */
    double freed;      /* s: the first close (opening below ROD_JAW_CLOSED) of the jaws
                          that handed the needle over here, after they have opened
                          (INFINITY: never): from then on they are ordinary jaws */
} rod_needle_grasp;

/* An instrument's grasp as the run sees it now (rod_state). */
typedef struct rod_grasp_state {
    int held;          /* 1: the closed jaws hold the thread */
    int closed;        /* 1: the jaws were closed at the last step (a closing is an edge) */
    double s;          /* m: the arc length of the thread in the jaws now */
    double local[3];   /* m: the held point in the instrument's frame (from its tip) */
    double t_on;       /* s: when the jaws closed on it */
    double force[3];   /* N, global: the force the thread exerts on the jaws there */
    double touch[3];   /* N, global: the force the thread exerts on its parts (jaws,
                          shanks, box lock) by contact at the last step, besides the grasp */
    int log;           /* its entry in rod_state grasp_log, or -1 (the log is full) */
} rod_grasp_state;

/* One grasp of the run, for its report (rod_state grasp_log). */
typedef struct rod_grasp_record {
    int instrument;    /* index in the model's instruments */
    double t_on;       /* s: when the jaws closed on the thread */
    double t_off;      /* s: when they opened; -1 while they hold it */
    double s;          /* m: the arc length grasped at t_on */
    double force;      /* N: the largest force the thread exerted on the jaws while held */
} rod_grasp_record;

/* The most grasps a run reports. */
#define ROD_MAX_GRASP_LOG 32

/* A cut of the thread (sim/cut.h): asked for by scissors closing across
 * it, or by the scene ([cut]); made after the step that asked. */
typedef struct rod_cut_request {
    int pending;       /* 1: a cut is due after this step */
    int instrument;    /* the scissors' index in the model's instruments; -1: the scene's */
    double s;          /* m: where, as arc length of the thread as it is now (node 0 at 0) */
} rod_cut_request;

/* One cut of the run, for its report (rod_state cut_log). Arc lengths are
 * the uncut thread's (from its first node). */
typedef struct rod_cut_record {
    int instrument;    /* index in the model's instruments; -1: the scene's [cut] */
    double t;          /* s: when */
    double s;          /* m: where the blades crossed the thread */
    double removed;    /* m: the length of the piece taken away */
    int side;          /* 0: the root's side was removed, 1: the tip's */
} rod_cut_record;

/* The most cuts a run makes. */
#define ROD_MAX_CUTS 8

struct rod_cut_thread; /* sim/cut.h: the model of the thread left after cuts */

/* A cut the scene gives ([cut], repeatable): at time t the thread is cut
 * at arc length s of the uncut thread (sim/cut.h). */
typedef struct rod_cut_event {
    double t;          /* s */
    double s;          /* m, from the uncut thread's first node */
} rod_cut_event;

/* A puncture as the run sees it now (rod_state). */
typedef struct rod_puncture_state {
    double point[3];   /* m, global: where the tissue holds the thread */
    double s;          /* m: the arc length of the thread passing through it now */
    double friction;   /* Coulomb coefficient along the thread */
    double force[3];   /* N, global: the force the thread exerts on the tissue there */
    int surface;       /* index of the tissue surface it was made in; -1: given in the scene */
    int track;         /* 1: a point of the needle's track inside the tissue (not where the
                          thread enters or leaves it) */
    /* in an elastic pad (rod_surface.solid): the material point it moves with */
    int linked;        /* 1: tet, bary, offset and compliance are set */
    int tet;           /* the pad's tet holding it */
    double bary[4];    /* its barycentric weights there */
    int patch_nodes;   /* the pad's nodes the thread bears on (tissue_patch_weights): */
    int patch_node[ROD_PATCH_NODES];      /* their indices */
    double patch_weight[ROD_PATCH_NODES]; /* their shares of the force (sum 1) */
    double offset[3];  /* m: point - the material point's position (constant) */
    double compliance[9]; /* m/N, 3 x 3 row-major: the point's static displacement per
                             newton at it, at the pad's last equilibrium */
    double cross[ROD_MAX_PUNCTURES][9]; /* m/N, 3 x 3 row-major each: how far the point moves
                             per newton at puncture l of the same pad (l != this one; 0 for
                             the others), at the pad's last equilibrium */
    double pad_force[3];  /* N: the force on the pad there at its last equilibrium */
    long compliance_factor; /* the pad's factorisation the compliance was taken from */
} rod_puncture_state;

/* Which physics a run models (scene [physics]). Switching one off removes
 * its cost where a scheme can exploit it, and says so. */
typedef struct rod_physics {
    int twist;          /* 1: torsion dynamics; 0: twist quasi-static (no torsional rotary
                           inertia), so a scene without twisting load does not pay for
                           torsion waves */
    int rotary_inertia; /* 1: rho I1, rho I2, rho J; 0: none (rotations quasi-static) */
    int gravity;        /* 1: [loads] gravity and distributed_force act; 0: the scene
                           reader leaves distributed_force at 0 */
    int damping;        /* 1: [loads] damping acts; 0: the scene reader leaves it at 0 */
    int planar;         /* 1: when every load lies in the x-y plane, schemes that can solve the
                           planar problem (exact, fewer unknowns); 0: always 3-D */
} rod_physics;

/* A time table: rows of (t, factor) when columns == 2, scaling the scene's
 * force and moment, or (t, fx, fy, fz, mx, my, mz) when columns == 7,
 * replacing them. Times strictly increase. Owned by the model's creator. */
typedef struct rod_table {
    int rows;
    int columns;   /* 2 or 7 */
    double *data;  /* (rows x columns), s then N / N m */
} rod_table;

typedef struct rod_profile {
    rod_profile_kind kind;
    double t1, t2; /* s; meaning per kind above */
    rod_table table;
} rod_profile;

/* A stretch of the rod whose grid is finer (scene [rod] refine): segments
 * in s0 .. s1 are `factor` times shorter than outside (sim/rod_grid.h). */
typedef struct rod_refine {
    double s0, s1;     /* m, arc length from the root, 0 <= s0 < s1 <= L */
    double factor;     /* 1 < factor <= ROD_MAX_REFINE_FACTOR */
} rod_refine;

#define ROD_MAX_REFINES 8
#define ROD_MAX_REFINE_FACTOR 100.0

/* Options of the run: which scheme, its step, how long. */
typedef struct rod_options {
    rod_scheme_kind scheme;
    double dt;                   /* s; <= 0 means auto */
    double duration;             /* s of simulated time */
    double theta;                /* implicit scheme: 1 = backward Euler, 0.5 = Crank-Nicolson */
    double newton_tolerance;     /* implicit/static: relative residual to stop Newton */
    int newton_max_iterations;   /* implicit/static */
    int iteration_budget;        /* implicit: when > 0, the Newton iterations a step may spend
                                    on each of its tries (the step with its splits, then up to
                                    two retries with contact); 0: the scheme's own (4000).
                                    rodsim live bounds a line's work with it */
    int exact_rotation;          /* thesis scheme: 1 = exact exponential map with angle |u| ds;
                                    0 = (4.6) literally, with sin(ds) and 1 - cos(ds) */
} rod_options;

/* The model: fixed for a run. Fill the inputs (rod_model_default() gives
 * table 1 of the thesis), then call rod_model_derive(). */
typedef struct rod_model {
    /* inputs: geometry and material (scene [rod]) */
    double length;               /* L, m */
    double diameter;             /* d, m */
    double density;              /* rho, kg/m^3 */
    double youngs_modulus;       /* E, Pa */
    double shear_modulus;        /* G, Pa */
    int nodes;                   /* NS >= 3 */
    double rotary_inertia_scale; /* multiplies the physical rotary inertia; 1 = physical */

    /* inputs: loads (scene [tip] and [loads]) */
    rod_load_frame tip_frame;
    double tip_force[3];          /* N, on tip_frame */
    double tip_moment[3];         /* N m, on tip_frame */
    rod_profile profile;          /* time profile of the tip force and moment */
    double distributed_force[3];  /* N/m along the rod, global x y z (gravity = m g) */
    double linear_damping;        /* N s/m^2: force per length = -c v */
    double angular_damping;       /* N m s/m: moment per length = -c_w omega */

    /* inputs: end conditions and physics switches (scene [ends], [physics]) */
    rod_end_kind root_end;        /* clamped (default), pinned or free */
    rod_end_kind tip_end;         /* free (default), pinned or clamped */
    double root_slide[3];         /* unit direction, global, along which the held root slides
                                     freely; 0 0 0 (default): held in place or driven */
    double tip_slide[3];          /* the same for the tip (1 0 0: Euler's sleeve) */
    int slide_twist_held[2];      /* root, tip: 1 when a clamped end on a slide does not turn
                                     about it (a carriage that slides but does not turn, as
                                     in the twisted-rod experiments under tension); 0
                                     (default): it turns freely (Greenhill's sleeve).
                                     Implicit scheme only */
    rod_path *root_motion;        /* owned; NULL (default): a held root stays where it starts */
    rod_path *tip_motion;         /* owned; NULL: a held tip stays where it starts */
    double needle_radius;         /* m, a curved needle whose back is at the driven tip; 0: none
                                     (drawn only; no mechanics) */
    rod_physics physics;          /* all on by default */

    /* inputs: starting shape and state (scene [rod]) */
    double origin[3];             /* m, global: the root at t = 0 (default 0 0 0) */
    double direction[3];          /* unit, global: the initial tangent of a straight rod
                                     (default 1 0 0); d1, d2 follow by the smallest rotation
                                     of (y, z) that takes x to it */
    double *initial_shape;        /* (nodes x 3) m, global, owned: the starting centreline,
                                     resampled to equal arc lengths ds; NULL: straight from
                                     origin along direction. Frames are twist-free along it
                                     (parallel transport from the root's) */
    double settle;                /* s: the thread's motion from its starting shape before
                                     t = 0, toward rest (sim/settle.h); 0 (default): none */
    double *initial_frames;       /* (nodes x 9), owned: the frames at t = 0 when the start
                                     settled (sim/settle.h), initial_shape then its centreline;
                                     NULL: twist-free along the shape */
    double shape_tip_moved;       /* m: how far the resampling to NS nodes put the tip from
                                     the shape's last point (0: straight, or given at NS) */
    double shape_moved;           /* m: the farthest the resampled nodes stray from the
                                     shape's points (0 as shape_tip_moved) */
    char adjusted[512];           /* for people: what rod_model_derive moved to make the
                                     inputs agree (an end's path shifted onto the resampled
                                     end), or "" */
    double intrinsic_curvature[3];/* u0, 1/m, director components: M = B (u - u0) (thesis
                                     nomenclature; (3.5) with a rest curvature) */
    double initial_velocity[3];   /* m/s, global, the same at every node at t = 0 */
    int self_contact;             /* 1 (default): non-neighbouring strands touch at the rod's
                                     diameter (implicit scheme, 3-D); 0: they pass */
    double self_friction;         /* Coulomb coefficient between strands (scene rod.friction) */
    int between_rods;             /* 1: other rods of the scene may touch this one (sim/rod_set.h):
                                     the implicit scheme takes contact's path (line search,
                                     contact's Jacobian) even without surfaces; the set makes
                                     its cuts and takes its grasps; 0 (default) */
    int pad_by_set;               /* 1: its elastic pad is shared with other rods of the scene
                                     (sim/rod_set.h), which couple it after every rod's step:
                                     the rod's own step only links its punctures; 0 (default) */

    /* inputs: loads along the rod (scene [point_load], [loads]) */
    int point_load_count;
    rod_point_load *point_loads;  /* (point_load_count), owned */
    double distributed_moment[3]; /* N m/m along the rod, global x y z */

    /* inputs: obstacles (scene [surface], [puncture]) */
    int surface_count;
    rod_surface *surfaces;        /* (surface_count), owned */
    int puncture_count;
    rod_puncture *punctures;      /* (puncture_count), owned */
    int instrument_count;         /* scene [instrument], at most ROD_MAX_INSTRUMENTS */
    rod_instrument *instruments;  /* (instrument_count), owned */
    int needle_grasp_count;       /* scene [needle_grasp], times increasing */
    rod_needle_grasp needle_grasps[ROD_MAX_NEEDLE_GRASPS];
    /* 1: [ends] tip_motion given with a needle = yes holder: the needle's
     * path whole (a rodsim live record's, its handovers in it); the
     * holder's path moves its jaws only and no grasp hands a path over */
    int needle_path_given;
    int cut_event_count;          /* scene [cut]: cuts at given times, without scissors */
    struct rod_cut_event *cut_events; /* (cut_event_count), owned */

    rod_options options;

    /* inputs: the grid (scene [rod] refine); refine_count 0: uniform, ds apart */
    int refine_count;
    rod_refine refine[ROD_MAX_REFINES];

    /* derived by rod_model_derive() */
    double ds;                   /* m, L / (NS - 1)   (4.1): the spacing of a uniform grid,
                                    the mean spacing of a graded one */
    double *segment_length;      /* (nodes - 1) m, owned: a graded grid's rest lengths, segment
                                    j from node j to j + 1 (sim/rod_grid.h); NULL: uniform, every
                                    segment ds. Made by the first rod_model_derive with refine
                                    intervals, refilled in place by later ones (same nodes) */
    double area;                 /* m^2, pi d^2 / 4 */
    double second_moment;        /* I1 = I2 = pi d^4 / 64, m^4 */
    double polar_moment;         /* J = pi d^4 / 32, m^4 */
    double stiffness[3];         /* B = diag(E I, E I, G J), N m^2   (3.5) */
    double mass_per_length;      /* m = rho A, kg/m */
    double rotary_inertia[3];    /* rho (I, I, J) * rotary_inertia_scale, kg m; zero where
                                    physics.rotary_inertia / physics.twist are off */
} rod_model;

/* The state: everything that changes during a run. Arrays are allocated by
 * rod_state_create() for model->nodes nodes. */
typedef struct rod_state {
    int nodes;
    double time;              /* s */
    double *position;         /* (nodes x 3), m, global x y z */
    double *frame;            /* (nodes x 9), row-major 3x3 rotation Q with columns d1 d2 d3
                                 in global components: d_k = column k of Q */
    double *velocity;         /* (nodes x 3), m/s, director components */
    double *angular_velocity; /* (nodes x 3), rad/s, director components */
    double *darboux;          /* (nodes x 3), 1/m, director components; see `staggered` */
    double *contact_force;    /* (nodes x 3), N, director components; see `staggered` */
    int staggered;            /* 0: darboux and contact_force live at the nodes;
                                 1: entry i < nodes-1 lives at the segment midpoint i+1/2
                                 (in the frame there) and entry nodes-1 is the tip value */
    double end_force[2][3];   /* N, global: the force the rod exerts on what holds its root
                                 [0] and its tip [1] (what a needle holder feels); 0 at a
                                 free end. Set by every step of a scheme that models ends */
    double end_moment[2][3];  /* N m, global, likewise */
    double *surface_force;    /* (nodes x 3), N, global: the force the surfaces exert on
                                 each node (contact and friction), 0 where none touches */
    double *self_force;       /* (nodes x 3), N, global: the force other strands of the rod
                                 exert on each node (self-contact), 0 where none touches */
    double strand_gap;        /* m: the closest two non-neighbouring segments at the step's
                                 end, of those within the self-contact candidates' reach
                                 (all that could touch); INFINITY when none is (implicit
                                 scheme) */
    int puncture_count;       /* punctures the thread passes through now */
    rod_puncture_state puncture[ROD_MAX_PUNCTURES];
    rod_grasp_state grasp[ROD_MAX_INSTRUMENTS]; /* one per instrument of the model */
    int grasp_log_count;
    rod_grasp_record grasp_log[ROD_MAX_GRASP_LOG]; /* the run's grasps, in order */
    /* trimming (sim/cut.h): after a cut, `nodes` counts the nodes left (the
     * arrays keep their size) and cut holds their model */
    int first_node;           /* the uncut thread's node that is node 0 now (0: none cut) */
    rod_cut_request cut_request;
    int cut_count;
    rod_cut_record cut_log[ROD_MAX_CUTS]; /* the run's cuts, in order */
    struct rod_cut_thread *cut; /* shared by copies (counted); NULL: the thread is whole */
} rod_state;

/* Outcome of a step or a solve. */
typedef enum {
    ROD_OK = 0,
    ROD_UNSTABLE,       /* the scheme diverged: message says what and what would work */
    ROD_NO_CONVERGENCE, /* Newton did not converge */
    ROD_FAILED          /* out of memory or another failure */
} rod_status;

typedef struct rod_report {
    char message[768];      /* for people: what diverged, the limit broken, what would work */
    char warning[512];      /* for people, on success: a caveat of the answer (e.g. the side
                               chosen at a symmetric bifurcation), or ""; the first one stays */
    double suggested_dt;    /* s, a step that would work, or 0 when none is known */
    double suggested_scale; /* a rotary_inertia_scale that would work, or 0 */
    int newton_iterations;  /* of the last step (implicit, static) */
    long jacobian_builds;   /* implicit: Jacobians built and factored since rod_solver_init
                               (cumulative, for benches and tests); other schemes leave it */
    long newton_total;      /* implicit: Newton iterations since rod_solver_init, those of
                               attempts that failed and split included (cumulative) */
    long resorted_steps;    /* implicit: steps that every usual attempt failed and the last
                               resort solved (src/sim/implicit/step.c), cumulative */
    double resorted_first;  /* s: the time the first of them started at */
} rod_report;

#endif
