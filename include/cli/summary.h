/* summary.h: `rodsim run --summary FILE`: one JSON object that says how a
 * run ended, whatever its outcome, for a machine (a CI job, a sweep driver)
 * to read instead of the prose. The run fills a run_summary as it goes;
 * summary_write turns it into JSON (docs/commands.md lists every field).
 *
 * The writer is a small one: numbers in the fewest of 15 to 17 significant
 * digits that read back as the same double, non-finite numbers as null, strings escaped (quotes,
 * backslashes, control characters as \u00XX). A field that was never known
 * is left out. */
#ifndef RODSIM_SUMMARY_H
#define RODSIM_SUMMARY_H

#include <stddef.h>
#include <stdio.h>

#define SUMMARY_TEXT_LEN 1024
#define SUMMARY_MAX_WARNINGS 16
#define SUMMARY_MAX_FILES 8
#define SUMMARY_MAX_KNOT_CHANGES 32
#define SUMMARY_MAX_PUNCTURES 16
#define SUMMARY_MAX_GAPS 512

/* A knot change: when (s) and the type after it. */
typedef struct summary_knot_change {
    double t;
    char type[96];
    char how[32]; /* at an end: "tied at the root end", "slipped off the tip end", ... (as
                     knot_track_how_text), "" for a pass-through or not told */
} summary_knot_change;

/* A puncture: made at t (s; 0 for one the scene gives), its point (m,
 * global) and the force the thread exerts on the tissue there at the run's
 * end (N, global); with several rods, the rod whose thread it holds ("":
 * the single rod, left out of the JSON). */
typedef struct summary_puncture {
    double t;
    double point[3];
    double force[3];
    char rod[32];
} summary_puncture;

/* Several rods on an elastic pad: each rod with punctures in it is a
 * stitch, the wound's opening measured at its punctures' mean place along
 * the wound per output frame (stitch_gap, beside wound_gap's times). */
#define SUMMARY_MAX_STITCHES 8

/* A grasp: the instrument's name (and the rod's, of several), when its jaws closed on the thread and
 * opened (s; t_off < 0: they hold it at the run's end), the arc length
 * grasped (m) and the largest force the thread exerted on the jaws (N). */
#define SUMMARY_MAX_GRASPS 32
typedef struct summary_grasp {
    char instrument[32];
    char rod[32];      /* the rod it took, in a scene of named rods ("": the one rod) */
    double t_on, t_off, s, force;
} summary_grasp;

/* A cut of the thread (sim/cut.h): the scissors' name ("" for the scene's
 * [cut]), the rod it cut in a scene of named rods ("": the one rod), when
 * (s), where on the uncut thread (m of arc length from its first node) and
 * the length of the piece taken away (m). */
#define SUMMARY_MAX_CUTS 8
typedef struct summary_cut {
    char instrument[32];
    char rod[32];
    double t, s, removed;
} summary_cut;
/* The needle handed over (scene [needle_grasp]): when (s), from whose jaws
 * to whose. */
#define SUMMARY_MAX_NEEDLE_GRASPS 8
typedef struct summary_needle_grasp {
    char from[32], to[32];
    double t;
} summary_needle_grasp;
/* A rod's knot at the last output frame, as the single rod's knot fields
 * below: its name, Alexander polynomial's coefficients, determinant,
 * signature, the rope in it and every change between output frames. */
typedef struct summary_rod_knot {
    char type[96];
    long long alexander[32];
    int terms;
    long long determinant;
    int has_signature, signature;
    double rope_d;        /* diameters; NAN: not measured */
    int change_count;
    summary_knot_change changes[SUMMARY_MAX_KNOT_CHANGES];
} summary_rod_knot;

/* One rod of a scene of several ([rod NAME]): its name, node count, tip
 * (m, global), ends (as the single rod's below), the force the other
 * rods exert on it at the end (N, global: contact and reactions) and its
 * own knot (its centreline closed far outside it). */
#define SUMMARY_MAX_RODS 8
typedef struct summary_rod {
    char name[32];
    int nodes;
    double tip[3];
    int has_end[2];
    double end_force[2][3];
    double end_moment[2][3];
    double contact_force[3];
    double min_strand_gap_d; /* diameters; INFINITY: strands never near (left out) */
    int has_knot;         /* 1: the rod can knot (or was knotted) and its knot was identified */
    summary_rod_knot knot;
} summary_rod;

/* The knot two rods of several make together (their centrelines closed
 * into one curve, sim/geometry/knot_across.h): the rods' names and the
 * knot as a rod's (rope_d NAN). For the first SUMMARY_MAX_KNOTS_ACROSS
 * pairs in the scene's order. */
#define SUMMARY_MAX_KNOTS_ACROSS 8
typedef struct summary_knot_across {
    char rods[2][32];
    summary_rod_knot knot;
} summary_knot_across;

/* What a run tells; every `has_` flag says the part is known (else left
 * out of the JSON). Strings are copied in (fixed size: no ownership). */
typedef struct run_summary {
    /* "ok" | "refused" | "unstable" | "failed" | "stopped"; NULL: from exit_code */
    const char *status;
    int exit_code;
    char message[SUMMARY_TEXT_LEN];           /* why the run did not succeed ("" when ok) */
    int warning_count;
    char warnings[SUMMARY_MAX_WARNINGS][SUMMARY_TEXT_LEN];
    char scene[256];      /* the scene's name ("" unknown) */
    char scheme[32];      /* "" unknown */
    int has_run;          /* 1: steps, frames, t_end known */
    long long steps, frames;
    double t_end;         /* s, the simulated time reached */
    int has_video_rate;   /* 1: fps and speed known */
    int fps;              /* video frames per video second (render.fps) */
    double speed;         /* render.speed: simulated seconds per video second */
    double cpu_s, wall_s; /* s: the whole command's CPU (user + sys) and wall time */
    double step_cpu_s;    /* s: the CPU of the steps alone (0: none taken) */
    char gl[16];          /* "egl" | "osmesa": the backend that drew; "" none */
    int file_count;
    char files[SUMMARY_MAX_FILES][SUMMARY_TEXT_LEN];
    /* the rod ("rod": today's single rod) */
    int has_rod;
    int nodes;
    double tip[3];        /* m, global */
    int has_end[2];       /* root, tip: 1 when held (a free end exerts nothing) */
    double end_force[2][3];  /* N: what the rod exerts on that end's support */
    double end_moment[2][3]; /* N m */
    int has_knot;         /* 1: the scene can knot and its knot was identified */
    char knot_type[96];
    long long knot_alexander[32];
    int knot_terms;
    long long knot_determinant;
    int knot_has_signature, knot_signature;
    double rope_in_knot_d; /* diameters; NAN: not measured */
    int knot_change_count;
    summary_knot_change knot_changes[SUMMARY_MAX_KNOT_CHANGES];
    double min_strand_gap_d; /* diameters; INFINITY: strands never near (left out) */
    /* several rods: rod_count > 0 lists these (has_rod then unused) */
    int rod_count;
    summary_rod rods[SUMMARY_MAX_RODS];
    int knot_across_count;
    summary_knot_across knots_across[SUMMARY_MAX_KNOTS_ACROSS];
    int puncture_count;
    summary_puncture punctures[SUMMARY_MAX_PUNCTURES];
    int grasp_count;
    summary_grasp grasps[SUMMARY_MAX_GRASPS];
    int cut_count;
    summary_cut cuts[SUMMARY_MAX_CUTS];
    int needle_grasp_count;     /* the handovers the run reached */
    summary_needle_grasp needle_grasps[SUMMARY_MAX_NEEDLE_GRASPS];
    /* the closest two instruments came over the run, from their paths
     * (sim/instrument_overlap.h): their capsules' surfaces apart (m; below
     * 0: overlapping by that much; INFINITY: fewer than two instruments,
     * left out), when (s), whose (names) and which parts ("jaw", "shank",
     * "box lock") */
    double min_instrument_gap;
    double min_instrument_gap_t;
    char min_instrument_gap_between[2][32];
    char min_instrument_gap_parts[2][16];
    /* an elastic pad ([surface] model = elastic) */
    int has_tissue;
    double tissue_max_displacement; /* m: the farthest a pad node is from its rest place,
                                       over the output frames */
    int gap_count;
    double wound_gap[SUMMARY_MAX_GAPS][2]; /* t s, gap m: the wound's opening at the stitch
                                              (the pad's punctures' mean place along the
                                              wound; without one, the widest) per output
                                              frame, the first SUMMARY_MAX_GAPS; several
                                              rods: the widest along the wound */
    int stitch_count;
    char stitch_rod[SUMMARY_MAX_STITCHES][32];
    double stitch_gap[SUMMARY_MAX_GAPS][SUMMARY_MAX_STITCHES]; /* m, at wound_gap's times */
} run_summary;

/* An empty summary: nothing known, rope and gap unknown. */
void summary_init(run_summary *s);

/* Adds a warning (copied, cut to SUMMARY_TEXT_LEN); past the maximum dropped. */
void summary_add_warning(run_summary *s, const char *text);
/* Adds a file written (copied); past the maximum dropped. */
void summary_add_file(run_summary *s, const char *path);
/* Sets the message unless one is set already (the first cause wins). */
void summary_set_message(run_summary *s, const char *text);

/* The status word for an exit code when none was set: 0 ok, 2 refused, else failed. */
const char *summary_status(const run_summary *s);

/* Writes the object (and a newline) to f. 0, or -1 when the write failed. */
int summary_print(FILE *f, const run_summary *s);

/* Writes it to `path` ("-": standard output) through base/outfile.h (a
 * temporary name, then renamed: whole or not at all). 0, or -1 with err. */
int summary_write(const char *path, const run_summary *s, char *err, size_t errlen);

/* JSON pieces, for the summary and its tests: a string with its quotes
 * (escaped), a number (shortest round trip; null when not finite). */
void summary_json_string(FILE *f, const char *text);
void summary_json_number(FILE *f, double x);

#endif
