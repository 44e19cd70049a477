/* work.h: the implicit scheme's work (implicit_work), internal to the
 * implicit room (src/sim/implicit/): the layout of a step's unknowns, the
 * ends' conditions, and every array a step uses, sized once at creation
 * (no allocation in the step loop). The equations: residual.h. */
#ifndef RODSIM_SIM_IMPLICIT_WORK_H
#define RODSIM_SIM_IMPLICIT_WORK_H

#include <stddef.h>

#include "base/band.h"
#include "sim/contact/contact.h"
#include "sim/contact/self_contact.h"
#include "sim/rod.h"
#include "sim/rod_types.h"

/* Unknowns per block: N(3), omega(3) in 3-D; N(2), v(2), omega_2 in the
 * plane. Half bandwidth kl = ku of the Jacobian in that block order: 8 in 3-D
 * (the angular momentum rows of node b reach omega of nodes b-1 and b+1, and
 * the constraint rows N of the segments beyond, through v) and 5 in the
 * plane; every other coupling is nearer. */
#define BLOCK 6
#define BAND 8
#define BLOCK_PLANAR 5
#define BAND_PLANAR 5
/* With punctures, a block's unknowns reach the rows of blocks b-2..b+2 (a
 * puncture's force couples the two nodes of its segment; 5 colours), but
 * only through the end-of-step velocities: a node's velocity reaches the
 * free velocities of its neighbours (add_contact_jacobian), so the (3.14)
 * rows of block b (its first 3) reach the forces (first 3) of blocks b-1
 * .. b+2, and those of block b+1 the forces of block b-1: half bandwidth
 * 2 BLOCK + 2 = 14, not 2 BLOCK + BLOCK - 1 = 17 (each factorisation of a
 * suture 0.68 of the cost) */
#define BAND_PUNCTURE 14

/* One end's condition, read once from the model (index 0 root, 1 tip). */
typedef struct end_condition {
    int held;            /* position held: in place, driven, or on its slide line */
    int sliding;         /* held on the line through its start along `slide` (through the
                            path's point along the path's turn of it, when driven) */
    int clamped;         /* frame held (clamped, not sliding): from the path, no unknowns */
    int hold_omega[3];   /* omega components (director) held at zero by the end */
    double slide[3];     /* unit, global (a driven sleeve's: at t + dt of this step) */
    double slide0[3];    /* unit, global: the slide at the start (a driven sleeve turns it) */
    double line_vel1[3]; /* m/s, global: a driven sleeve's velocity across its slide at the
                            end node, at t + dt (0 when not driven) */
    const rod_path *path;/* driven, or NULL */
    int have_initial;    /* initial_frame and anchor are known */
    double anchor[3];    /* m, global: where a held end started (a point of a slide's line) */
    double correction[3];/* m/s: this step's return to the anchor (to its line when sliding)
                            of what rounding moved the end, so that held ends never drift */
    double initial_frame[9]; /* Q_end(0): a driven clamped end's frame is R(t) Q_end(0) */
    /* this step, from the path (independent of the Newton iterate) */
    double vbar[3];      /* (r(t+dt) - r(t)) / dt, global, m/s */
    double vel1[3];      /* velocity at t + dt, global, m/s */
    double pos1[3];      /* position at t + dt, global, m */
    double frame1[9], frame_th[9]; /* a clamped end's frame at t + dt and at the theta point */
    double omega1[3];    /* a clamped end's angular velocity at t + dt, director */
    /* left over from the last residual: what the support exerts on the rod */
    double reaction[3];  /* N, global */
    double reaction_moment[3]; /* N m, global */
} end_condition;

/* Why a factorisation was made (implicit_work.builds_by): the first of the
 * run; a step's start with none (after an attempt that failed and split, a
 * retry, the band's width changed); a step's start on a factorisation the
 * last step found stale, contact's part renewed or the whole; a step of
 * another dt than the factorisation's; a step whose strands asked for a
 * new B (PAIRS_SLOW_STEP); a slow iteration, contact's part or the whole;
 * between steps (implicit_refresh) */
enum {
    BUILD_FIRST, BUILD_LOST, BUILD_STALE_CONTACT, BUILD_STALE_WHOLE, BUILD_DT, BUILD_PAIRS,
    BUILD_SLOW_CONTACT, BUILD_SLOW_WHOLE, BUILD_BETWEEN, BUILD_WHY
};

typedef struct implicit_work {
    int nodes, blocks, unknowns;
    int first;         /* first node with an omega block: 0 when the root may turn, else 1 */
    end_condition ends[2];
    double *point_force, *point_moment; /* (nodes x 3) global, unscaled point loads; NULL if none */
    int distributed_moment; /* 1: the model has one */
    double point_factor; /* theta-mean of the profile factor over the step */
    double *vbar;      /* (nodes x 3) global, the step's mean velocity (3-D) */
    double *pos0;      /* (nodes x 3) global, positions at the start of the step */
    /* contact with the scene's surfaces and punctures (sim/contact/contact.h) */
    rod_contact contact;
    int has_contact;   /* 1: surfaces or punctures (Newton with a line search) */
    /* the contact's part of the Jacobian, in closed form (add_contact_jacobian) */
    double *band_smooth;   /* (ldab x unknowns) the rod's part of the Jacobian (the residual
                              without contact and punctures), unfactored */
    int smooth_kl;         /* the half bandwidth band_smooth was built with, 0: none */
    double smooth_dt;      /* s, the step it was built for */
    int smooth_renewals;   /* contact-only renewals onto it at a step's start (newton) */
    /* what the factors in lu were made from, for a renewal of contact's
     * part that refactors only from the first column it changes
     * (implicit_refresh_contact_jacobian): contact's velocity maps and
     * touched nodes, the step and the ends' holds then; valid while lu
     * holds the factors of band_smooth plus that contact part */
    double *trail_jac;     /* (nodes x 27) velocity_jac */
    unsigned char *trail_touched; /* (nodes) */
    double trail_dt;
    int trail_held[2], trail_valid;
    int stale_start;       /* 1: this step's factorisation was dropped as stale (start.c) */
    int contact_off;       /* 1: the residual leaves contact and punctures out */
    int fd_only;           /* 1: this attempt takes the rod's part of the Jacobian by finite
                              differences (step's retry; rod_jacobian) */
    int contact_fd;        /* 1: this attempt takes the whole Jacobian by finite differences
                              (step's second retry) */
    int patient;           /* 1: this attempt lets Newton run past the contact stall test, up to
                              PATIENT_FACTOR x newton_max_iterations (step's last retry, held steps; newton.h) */
    long patient_steps;    /* steps since create that needed it (step.c's note_patient) */
    double patient_first;  /* s: the time the first of them started at */
    int patient_hold;      /* steps left that start patient (PATIENT_HOLD_STEPS) */
    int patience_used;     /* a patient attempt of this step went past the stall test or
                              newton_max_iterations */
    int last_resort;       /* 1: this attempt is the step's last resort (step.c): patient,
                              each sub-step starting from the last one's solution */
    long resorted_steps;   /* steps since create the last resort solved */
    double resorted_first; /* s: the time the first of them started at */
    double fd_step;        /* relative step of the finite-difference Jacobian */
    int reach;             /* blocks a block's unknowns reach: 1, or 2 with punctures */
    int max_reach;         /* the reach the band is sized for; a step uses 2 only while
                              punctures exist (start.c) */
    rod_puncture_state save_puncture[ROD_MAX_PUNCTURES];
    /* the grasps and their log at the step's start: a split step's half
     * that was accepted before its other half failed moved them, and the
     * retry starts from the start again (restore_state) */
    rod_grasp_state save_grasp[ROD_MAX_INSTRUMENTS];
    rod_grasp_record save_grasp_log[ROD_MAX_GRASP_LOG];
    int save_grasp_log_count;
    /* the cut asked for at the step's start (sim/cut.h): scissors that
     * closed in a discarded half asked for one where the thread was then */
    rod_cut_request save_cut_request;
    /* self-contact (sim/contact/self_contact.h): NULL when off */
    rod_self_contact *self;
    int frames_kept;       /* 1: the residual keeps the end-of-step frames, darboux1, d3mid1
                              and moment1 of its last evaluation (fd_jacobian's force
                              columns: the frames depend on omega alone) */
    /* contact with the other rods of a set (sim/contact/between_rods.h): NULL
     * when alone; set by rod_implicit_link, owned by the set's link */
    struct rod_cross *cross;
    int self_off;          /* 1 while the banded Jacobian is built: the pair forces act,
                              their laws are not evaluated (B does not depend on them) */
    double *node_push;     /* (nodes) m/s per N: a force's effect on each node's velocity
                              over the step (0 at a held end) */
    double self_motion;    /* m: the largest node displacement of the last step */
    int save_puncture_count;
    int planar;        /* 1: the planar problem (rod_model_loads_planar and physics.planar) */
    int block;         /* unknowns per block (BLOCK or BLOCK_PLANAR) */
    int var_kind[BLOCK_PLANAR > BLOCK ? BLOCK_PLANAR : BLOCK]; /* per component of a block:
                                    0 force, 1 velocity, 2 angular velocity */
    double *x;         /* (unknowns) current Newton iterate */
    double *dx;        /* (unknowns) correction */
    double *residual;  /* (unknowns) scaled residual at x */
    double *eval_x;    /* (unknowns) the x of the last evaluation when eval_valid */
    double eval_t, eval_dt;
    int eval_valid;    /* 1: the last residual evaluation (of any kind) was the whole
                          residual at eval_x, t, dt into residual, with contact's
                          velocity_jac recorded, and no self-contact pairs (whose
                          forces are unknowns beside x): residual.c's evaluated_at_x */
    double *perturbed; /* (unknowns) residual at a perturbed x */
    band_lu lu;        /* the Jacobian and its LU factors (half bandwidth lu.kl: BAND,
                          BAND_PLANAR or BAND_PUNCTURE; lu.rows with self-contact) */
    int have_factor;   /* lu holds a usable factorisation */

    /* start of the step */
    double *frame0;    /* (nodes x 9) */
    double *omega0;    /* (nodes x 3) director */
    double *vel0;      /* (nodes x 3) global */
    double *vel1;      /* (nodes x 3) global, end of the step: from N by (3.3)_1 (3-D) */
    double *d3mid0;    /* (nodes-1 x 3) */
    double *moment0;   /* (nodes-1 x 3) global, M_{i+1/2} */
    double *tipf0, *tipm0; /* (3) tip force and moment at the start, global */

    /* end of the step, for the iterate x */
    double *frame1;    /* (nodes x 9) */
    double *frame_th;  /* (nodes x 9) frame at the theta point (theta < 1; for theta = 1 the
                          residual reads frame1) */
    double *darboux1;  /* (nodes-1 x 3) */
    double *mid1;      /* (nodes-1 x 9) midpoint frames at the start of a run of steps;
                          scratch of the planar path */
    double *d3mid1;    /* (nodes-1 x 3) d3 at the midpoints */
    double *moment1;   /* (nodes-1 x 3) global */

    /* a saved copy of the state for step splitting */
    double *save_frame, *save_pos, *save_vel, *save_omega, *save_force;
    double save_time;

    double force_scale;  /* N, residual scaling of force balances */
    double moment_scale; /* N m, residual scaling of moment balances */
    double var_scale[3]; /* typical N (N), v (m/s), omega (rad/s) for FD steps */
    double jacobian_dt;  /* dt the factorisation was made for */
    long jacobian_builds; /* factorisations since create (rod_report.jacobian_builds) */
    long builds_by[BUILD_WHY]; /* the same by why they were made (for benches) */
    long newton_total;    /* Newton iterations since create (rod_report.newton_total) */
    int start_valid;     /* frame0, d3mid0, moment0 hold the state at start_time */
    double *x_last;      /* (unknowns) solution of the last step, ending at start_time */
    double *x_before;    /* (unknowns) solution of the step before it */
    double *x_before2;   /* (unknowns) solution of the step before that */
    double dt_last;      /* s, length of the last step; 0 when x_before is not usable */
    double dt_before;    /* s, length of the step before it; 0 when x_before2 is not usable */
    int quadratic;       /* the next first iterate from the last three solutions
                            (implicit_first_iterate_order) */
    double start_time;
    int budget;          /* Newton iterations left for the current step */
    int renew_pairs;     /* the next step renews B at its first iterate (PAIRS_SLOW_STEP) */
    int start_depth;     /* split_step attempts no step at a depth below this */
    int next_depth;      /* the next step's start_depth, for steps of depth_dt */
    double depth_dt;
    int split_depth;     /* the depth of the attempt single_step makes */
    int motion_depth;    /* the deepest attempt of this step that moved too far, or -1 */
    int depth_streak;    /* steps at next_depth with no such attempt */
    int deepest;         /* the deepest split of the current step (split_step) */
    int stale;           /* a chord iteration since the last whole build contracted by less
                            than IDLE_REFRESH_CONTRACTION (implicit_refresh renews it) */

    /* planar problem: frames are rotations about z by an angle phi (d3 at phi from +x) */
    double *phi0;      /* (nodes) rad, start of the step */
    double *phi1;      /* (nodes) rad, end of the step, for the iterate x */
    double *phi_th;    /* (nodes) rad, at the theta point */

    /* analytic_jacobian's scratch */
    double *jac_node;  /* (nodes x 18) d e / d omega at the end and at the theta point */
    double *jac_seg;   /* (nodes x 36) d d3 and d M of a segment / d omega of its two nodes */
} implicit_work;

/* N_{b-1/2} of the iterate x, b >= 1 (global components) */
static inline const double *block_force(const implicit_work *w, const double *x, int b)
{
    return &x[BLOCK * (b - w->first)];
}
/* omega_b of the iterate x, b >= first (director components) */
static inline const double *block_omega(const implicit_work *w, const double *x, int b)
{
    return &x[BLOCK * (b - w->first) + 3];
}

/* The scheme's work for the model, or NULL with a message when the scheme
 * cannot model it or memory runs out. */
implicit_work *implicit_create(const rod_model *m, char *err, size_t errlen);
void implicit_destroy(implicit_work *w);

#endif
