/* scheme_implicit.c: the rod equations (3.15) advanced by the theta-method
 * (backward Euler by default, Crank-Nicolson at theta = 1/2), all unknowns of
 * a step solved together by Newton's method on one banded system.
 *
 * Grid (staggered, which avoids the odd/even decoupling of one collocated
 * grid): velocity v and angular velocity omega at the nodes i = 0..NS-1;
 * Darboux vector u and contact force N at the segment midpoints i+1/2.
 *
 * Unknowns of a step, per block b = 1..NS-1 (6 each, 6 (NS-1) in all; a
 * root that may turn adds block 0, see Ends):
 *   N_{b-1/2}  contact force, global components (the multiplier of (3.14));
 *   omega_b    angular velocity at the end of the step, director components.
 * The velocity v_b at the end of the step (global components) is not an
 * unknown either: the linear momentum balance (3.3)_1 below is linear in v_b
 * and in N, so it gives v_b from the two contact forces beside node b; the
 * Newton system keeps (3.14) and (3.6)_2 (6 equations per node, half
 * bandwidth 8 instead of 9 unknowns and 11).
 * u is not an unknown: the frames advance by the exact exponential map
 *   Q_i(t+dt) = Q_i(t) exp(dt [omega_bar_i]x),  omega_bar = theta w(t+dt) + (1-theta) w(t)
 * (integrating (3.1)_2), and u_{i+1/2} = log(Q_i^T Q_{i+1}) / ds (integrating
 * (3.1)_1 exactly over the segment). The compatibility equation (3.10) then
 * holds exactly in discrete form and frames and curvature never drift apart.
 *
 * Equations, per block b:
 *   (3.14) inextensible, unshearable: (v_bar_{b} - v_bar_{b-1}) dt / ds
 *          = d3_{b-1/2}(t+dt) - d3_{b-1/2}(t), the time difference of
 *          r_{i+1} - r_i = ds d3_{i+1/2}; so r(t+dt) = r(t) + dt v_bar agrees
 *          with the centreline integrated from d3 (3.12).
 *   (3.6)_1 (written in the fixed frame, (3.3)_1) over the cell of node b,
 *          solved for v_b:
 *          m w_b (v_b - v_b(t)) / dt = N_{b+1/2} - N_{b-1/2} + w_b (T - c v_bar)
 *   (3.6)_2 in director components of node b:
 *          I w_b (omega - omega(t)) / dt + w_b omega_bar x I omega_bar
 *          = Q^T [ M_{b+1/2} - M_{b-1/2} + ds/2 (d3 x N)_{b+1/2} + ds/2 (d3 x N)_{b-1/2} ]
 *            - w_b c_w omega_bar,      M_{i+1/2} = Q_{i+1/2} B (u_{i+1/2} - u0)  (3.4)
 *   with w_b = ds inside and ds/2 at either end, where N_{NS-1/2} and
 *   M_{NS-1/2} are the tip force and moment (4.2) and the tip force has no
 *   arm; T holds the distributed force, and each node's point loads (times
 *   the profile factor) join its cell, as the distributed moment joins
 *   (3.6)_2.
 * Elastic terms are theta-weighted between the start and the end of the step.
 *
 * Ends (issue 10): node 0 and node NS-1 each have a cell of half length
 * ds/2. A free end's velocity comes from its cell's (3.3)_1 like any other;
 * a held end's is prescribed (zero, or its path's), and a sliding end's is
 * the free one projected on the slide, so v stays eliminated at every end
 * and the support's force is what that end's balance leaves over (computed
 * after Newton, never an unknown). The root's omega_0 is an unknown (block
 * 0, its first three entries unused) when the root may turn (pinned, free,
 * clamped sliding); rotations an end holds replace their (3.6)_2 rows by
 * omega_k = 0, and the leftover of those rows is the support's moment. A
 * clamped end's frame is its path's R(t) Q(0), not integrated. The band
 * does not grow: block 0 couples to block 1 as every block to its
 * neighbours. A held end's mean velocity over the step returns it to its
 * place (or its slide's line, or its path) from wherever rounding left it,
 * so held ends never drift; the centreline is chained from a held end.
 * The planar path models only today's cantilever; every other case is 3-D.
 *
 * Newton: the Jacobian is built in closed form (analytic_jacobian: one residual
 * evaluation and 3 x 3 algebra per node) or, in the plane and in a step's retry,
 * by finite differences with a 3-colouring of
 * the block-tridiagonal pattern (18 residual evaluations; 15 in the plane), factored by
 * a banded LU with partial pivoting (LAPACK's dgbtf2, written out), and reused across
 * iterations and steps while it keeps converging (refreshed when convergence slows).
 * Contact's part of it is in closed form (add_contact_jacobian). A step
 * whose Newton iteration fails is split in two, recursively, before giving up.
 */
#include "sim/rod.h"

#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/contact_law.h"
#include "sim/path.h"
#include "sim/rod_geometry.h"
#include "sim/scheme_implicit.h"
#include "sim/self_contact.h"
#include "sim/surface.h"
#include "base/vec3.h"
#include "base/vec3_lanes.h"

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
 * 2 BLOCK + 2 = 14, not 2 BLOCK + BLOCK - 1 = 17 (suture.ini: each
 * factorisation 0.68 of the cost) */
#define BAND_PUNCTURE 14
/* Loops over a column of L shorter than this run this length
 * (band_factor_kl) */
#define SHORT_COLUMN 8
/* Right-hand sides band_solve_rows takes at a time: two vectors a row */
#define ROWS_CHUNK (2 * LANES)
#define MAX_SPLIT_DEPTH 12
/* With self-contact, a step some attempt of which moved the strands too
 * far for the no-pass-through test (single_step: a converged solution
 * split all the same) starts the next steps already split to one level
 * below the deepest such attempt; after SPLIT_HOLD_STEPS steps with no
 * such attempt, one level coarser again. A loose knot swinging as it is
 * pulled tight moves too far within the scene's step at most of its steps
 * (overhand_tight.ini before 2 s, one run: about 1000 attempts in 420
 * steps, 162 of them converged and failed this test, 108 failed in
 * Newton; each attempt has a Jacobian of its own and its pairs' columns),
 * and there the halves' depth changes slowly. Only these failures count:
 * Newton's come one at a time, and foresight from them split steps that
 * would have passed (surgeons_knot.ini 1.2-1.6x the CPU, single runs).
 * Medians of five perturbed runs, paired: overhand_tight.ini 0.71 s of CPU
 * against 1.13, buckling_twist.ini 0.49 against 0.87, surgeons_knot.ini
 * 2.44 against 2.56, overhand.ini 2.11 against 2.06; a second pair 0.93
 * against 1.38, 0.56 against 0.93, 2.77 against 2.73, and overhand.ini
 * 2.44 against 2.25 (1.08x: its splits are rare, 50 in 3360 steps, and
 * each holds 4 steps split that would mostly have passed); holding 8
 * steps, overhand.ini 1.08x; 2, within the noise of 4; one level coarser
 * at once where twice the sub-steps' motion would have passed the test:
 * the sum 1.03x (buckling_twist.ini 1.16x). The
 * steps' sizes are still the scheme's own choice: each sub-step meets the
 * same tolerance and the same no-pass-through test. */
#define SPLIT_HOLD_STEPS 4
/* Self-contact's candidate pairs lie within this many diameters of one
 * diameter apart at the start of a step, at most (single_step) */
#define SELF_MARGIN 2.0
/* Newton iterations one step may spend, splits included (each attempt costs
 * one more; with contact twice: step's retry): bounds the time a hopeless
 * step takes (about 2 s at NS = 1001) instead of 4096 x 25 tries. Every loop
 * of the scheme is bounded: Newton by newton_max_iterations and this budget,
 * splitting by MAX_SPLIT_DEPTH and this budget, the rest by the node count.
 * 4000, not 2000: a plectoneme's snap with friction between its strands
 * (buckling_twist.ini) splits a 5 ms step to 1/64 and needed more than
 * 2000 (it failed at 11.1 s); it runs through with 4000 */
#define STEP_ITERATION_BUDGET 4000
/* Newton iterations over which a step with contact must halve its residual,
 * else it is split at once rather than after newton_max_iterations: a stall
 * at friction's turn between stick and slip seldom ends, and the half steps
 * mostly converge (suture.ini: 13.8 s of CPU instead of 15.9 s; 12.6 instead
 * of 17.7 in a loop of its steps) */
#define CONTACT_STALL 6
/* While self-contact pairs touch, Newton's line search keeps a trial point
 * whose residual is below the largest of the iterate's and the last
 * PAIRS_NONMONOTONE iterates' (a non-monotone line search: Grippo,
 * Lampariello and Lucidi, SIAM J. Numer. Anal. 23, 1986), not only below
 * the iterate's. A full step that moves a pair across friction's corner or
 * lets it part overshoots in that pair's residual for one iteration, and
 * the monotone search cut it to 1/128-1/256 of itself, iteration after
 * iteration, until CONTACT_STALL split the step: in buckling_twist.ini
 * such stalls of the pairs were 40 % of all Newton iterations. The sums of
 * the medians of 5 perturbed runs of the four knot scenes (scenes/README.md,
 * Self-contact), paired: 16.28 s of CPU monotone, 12.25 with a memory of
 * 2; 13.70 and 13.48 with 1 and 3 in another batch, 13.50 and 13.02 with 2
 * and 3 in a third. The step still ends only at the tolerance, and
 * CONTACT_STALL still asks for a halving within its iterations */
#define PAIRS_NONMONOTONE 3
/* With strands touching, a step that took at least PAIRS_SLOW_STEP Newton
 * iterations on a B made PAIRS_B_AGE or more steps before renews B at the
 * next step's first iterate. A knot slides through the rod as it
 * tightens, its sharp bends with it, and B, made where the knot was some
 * steps ago, is off where the strands now press: in overhand_tight.ini's
 * tied knot (t = 2 to 5 s) the scheme's own residual after the first
 * iteration stayed at 1e-8 to 1e-7 at the touching nodes, slowed one
 * iteration more and left another, 3.0 iterations a step. A B made afresh
 * at every step's start only over the span of the touching nodes (the rest
 * as old) gave 1.8 (the span alone suffices: its margin of 0 to 15 nodes
 * made no difference), a whole B every step the same at 2.3x the cost; this
 * rule 2.05 iterations a step, `make bench`'s whole pull once tied 3.2x the
 * step without contact instead of 3.7-4.0x (the renewal and the pairs'
 * columns solved again after it cost about 5 iterations). With a B at
 * least 5 steps old: 2.07 iterations and 3.5-3.8x; 20: 2.19 and 3.3x */
#define PAIRS_SLOW_STEP 3
#define PAIRS_B_AGE 10
/* A chord iteration that leaves the residual above the tolerance, having
 * contracted it by less than this, marks the factorisation stale, for the
 * next step to renew at its first iterate (single_step), or refresh()
 * between steps in live mode. Below newton()'s 0.25 and without its
 * floor of 10 tolerances: the contraction worsens over some tens of steps
 * (0.01 after a build; then 0.1 to 1 in the iterations below 1e-7 before
 * one of 0.3 above it rebuilds within a step, in bench_live at 1 kHz), so
 * a renewal at the first signs spares nearly every build within a step
 * (NS = 51: 369 in 10 s; 1 with renewals at 0.1, 318 with 0.1 and the
 * floor) */
#define IDLE_REFRESH_CONTRACTION 0.1
/* A step that starts on a factorisation the last one found stale renews
 * only contact's part of it (refresh_contact_jacobian, onto the rod's part
 * kept from the last whole build) up to this many times in a row, then the
 * whole. At 0.83 ms steps the thread's own Jacobian barely changes from one
 * step to the next, while which nodes touch, stick or slip does; a slow
 * iteration still renews the whole (newton). suture.ini: 5,076 whole builds
 * instead of 12,618 for 28,434 factorisations instead of 27,912 and 3.15
 * Newton iterations a step instead of 3.01, 0.93x the CPU (2.61 s against
 * 2.77-2.85 s, 4 paired runs); 2 in a row: 0.94x, 8: 0.96x, no limit:
 * 1.01x (3.63 iterations a step) */
#define CONTACT_START_REFRESHES 4
/* A chord iteration with contact (surfaces, punctures) and no strands
 * touching that contracts the residual by less than this renews the
 * Jacobian (contact's part first; newton()); 0.25 elsewhere. A renewal of
 * contact's part costs about two residual evaluations and a solve of
 * Newton's is saved by each iteration it spares: suture.ini with 0.05
 * instead of 0.25 takes 110,864 evaluations instead of 126,299 and 71,228
 * solves instead of 82,081, for 28,681 factorisations instead of 24,834
 * (0.1: 113,163, 73,035 and 27,339; 0.02: 109,697, 70,241 and 29,926);
 * 0.96x the CPU (6 and 8 paired runs); skin_drop.ini and `make bench`'s contact
 * cases the same */
#define CONTACT_SLOW_CONTRACTION 0.05
/* A needle's hole is made where the thread crosses the tissue, but not on
 * the segment at the needle's back (the held tip) farther toward it than
 * this fraction: the thread's point there moves with compliance (1 - f)^2
 * push, so a hole at f = 0.999 needs forces of tens of newtons to correct a
 * micron's miss at the next step (suture.ini with adaptive steps at 14.35
 * s: Newton failed even split 4096 ways; at dt = 0.8 ms, f = 0.9996 at 8.85
 * s, then a second hole 3 mm away and a stop at 9.11 s).
 * The crossing moves off the tip within a step or two (the thread lies
 * nearly flat as the needle dives: f falls from 0.99 to 0.82 in one step at
 * the first bite), and the hole is made there. With 0.995 the run goes
 * through at dt = 0.7, 0.8, 0.83, 0.9, 1.67 and 3.33 ms, E = 0.9 and 1.2
 * GPa; its holes lie within 0.106 mm of the needle path's (0.072 mm without
 * the rule, which failed at 0.8 ms; test_contact's test_needle_holes) */
#define NEEDLE_HOLE_CLEAR 0.995
/* Contact laws and their constants: sim/contact_law.h */

/* One end's condition, read once from the model (index 0 root, 1 tip). */
typedef struct end_condition {
    int held;            /* position held: in place, driven, or on its slide line */
    int sliding;         /* held on the line through its start along `slide` */
    int clamped;         /* frame held (clamped, not sliding): from the path, no unknowns */
    int hold_omega[3];   /* omega components (director) held at zero by the end */
    double slide[3];     /* unit, global */
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

typedef struct implicit_work {
    int nodes, blocks, unknowns;
    int first;         /* first node with an omega block: 0 when the root may turn, else 1 */
    end_condition ends[2];
    double *point_force, *point_moment; /* (nodes x 3) global, unscaled point loads; NULL if none */
    int distributed_moment; /* 1: the model has one */
    double point_factor; /* theta-mean of the profile factor over the step */
    double *vbar;      /* (nodes x 3) global, the step's mean velocity (3-D) */
    /* contact with the scene's surfaces (issue 11; see node_contact) */
    int surface_count;
    const rod_surface *surfaces;
    double *pos0;          /* (nodes x 3) global, positions at the start of the step */
    double *surface_force; /* (nodes x 3) global, N: what the surfaces exert, this iterate */
    /* the contact's part of the Jacobian, in closed form (add_contact_jacobian) */
    double *band_smooth;   /* (ldab x unknowns) the finite-difference Jacobian of the residual
                              without contact and punctures, unfactored */
    int smooth_kl;         /* the half bandwidth band_smooth was built with, 0: none */
    double smooth_dt;      /* s, the step it was built for */
    int smooth_renewals;   /* contact-only renewals onto it at a step's start (newton) */
    /* what the factors in band were made from, for a renewal of contact's
     * part that refactors only from the first column it changes
     * (refresh_contact_jacobian): contact's velocity maps and touched
     * nodes, the step and the ends' holds then; valid while band holds the
     * factors of band_smooth plus that contact part */
    double *trail_jac;     /* (nodes x 27) velocity_jac */
    unsigned char *trail_touched; /* (nodes) */
    double trail_dt;
    int trail_held[2], trail_valid;
    int stale_start;       /* 1: this step's factorisation was dropped as stale (single_step) */
    int contact_off;       /* 1: the residual leaves contact and punctures out */
    int fd_only;           /* 1: this attempt takes the rod's part of the Jacobian by finite
                              differences (step's retry; rod_jacobian) */
    int contact_fd;        /* 1: this attempt takes the whole Jacobian by finite differences
                              (split_step's retry) */
    int want_jacobian;     /* 1: node_contact and puncture_forces record velocity_jac */
    double *velocity_jac;  /* (nodes x 27) for a touched node b: d v_b / d u_{b-1}, d v_b / d u_b,
                              d v_b / d u_{b+1} (row-major 3x3), v the end-of-step velocity
                              after contact, u the free one from (3.3)_1 */
    unsigned char *touched;/* (nodes) 1: velocity_jac of the node is set (else the identity) */
    double *start_gap;     /* (nodes x surfaces x 7): each node's gap (m), outward normal and
                              nearest point (m, global) at the start of the step: fixed over
                              the step, so found once, not in every residual (prepare_contact) */
    double fd_step;        /* relative step of the finite-difference Jacobian */
    int reach;             /* blocks a block's unknowns reach: 1, or 2 with punctures */
    int contact;           /* 1: surfaces or punctures (Newton with a line search) */
    int max_reach;         /* the reach the band is sized for; a step uses 2 only while
                              punctures exist (single_step) */
    /* punctures of this step (from the state at its start; see puncture_force) */
    int puncture_count;
    struct {
        int j;             /* segment j..j+1 the thread passes the point through */
        double alpha;      /* fraction along it */
        double point[3], tangent[3], friction;
        double force[3];   /* N, global: what the tissue exerts on the thread, this iterate */
    } punct[ROD_MAX_PUNCTURES];
    unsigned *threaded;    /* (nodes): bit j set when the node is threaded through tissue
                              surface j (between its punctures): no contact with it */
    int needle_tissue;     /* 1: the driven tip carries a needle and a surface is tissue */
    rod_puncture_state save_puncture[ROD_MAX_PUNCTURES];
    /* self-contact (issue 12; sim/self_contact.h): NULL when off */
    rod_self_contact *self;
    int frames_kept;       /* 1: the residual keeps the end-of-step frames, darboux1, d3mid1
                              and moment1 of its last evaluation (fd_jacobian's force
                              columns: the frames depend on omega alone) */
    int self_off;          /* 1 while the banded Jacobian is built: the pair forces act,
                              their laws are not evaluated (B does not depend on them) */
    double *node_push;     /* (nodes) m/s per N: a force's effect on each node's velocity
                              over the step (0 at a held end) */
    double self_motion;    /* m: the largest node displacement of the last step */
    int save_puncture_count;
    int planar;        /* 1: the planar problem (rod_model_loads_planar and physics.planar) */
    int block, kl;     /* unknowns per block and half bandwidth (BLOCK/BAND or _PLANAR) */
    int var_kind[BLOCK_PLANAR > BLOCK ? BLOCK_PLANAR : BLOCK]; /* per component of a block:
                                    0 force, 1 velocity, 2 angular velocity */
    int ldab;
    double *x;         /* (unknowns) current Newton iterate */
    double *dx;        /* (unknowns) correction */
    double *residual;  /* (unknowns) scaled residual at x */
    double *eval_x;    /* (unknowns) the x of the last evaluation when eval_valid */
    double eval_t, eval_dt;
    int eval_valid;    /* 1: the last residual evaluation (of any kind) was the whole
                          residual at eval_x, t, dt into residual, with contact's
                          velocity_jac recorded, and no self-contact pairs (whose
                          forces are unknowns beside x): evaluated_at_x */
    double *perturbed; /* (unknowns) residual at a perturbed x */
    double *band;      /* (ldab x unknowns) LU factors, LAPACK band storage */
    lapack_int *pivot; /* (unknowns) */
    double *rows;      /* (unknowns x ROWS_CHUNK, 32-byte aligned) band_solve_rows' scratch
                          (with self-contact) */
    double *inv_diag;  /* (unknowns) 1 / U_jj of the factorisation: the back substitution
                          multiplies instead of dividing (a division's latency sits on its
                          serial critical path) */
    int *lower;        /* (unknowns) the length of column j's loops over L below the
                          diagonal: its trailing zeros trimmed, then padded with them to 8
                          where that is shorter than the band (band_factor_kl) */
    int *upper;        /* (unknowns) the first row of U's column j that is not zero */
    int have_factor;   /* band holds a usable factorisation */

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
    long newton_total;    /* Newton iterations since create (rod_report.newton_total) */
    int start_valid;     /* frame0, d3mid0, moment0 hold the state at start_time */
    double *x_last;      /* (unknowns) solution of the last step, ending at start_time */
    double *x_before;    /* (unknowns) solution of the step before it */
    double *x_before2;   /* (unknowns) solution of the step before that */
    double dt_last;      /* s, length of the last step; 0 when x_before is not usable */
    double dt_before;    /* s, length of the step before it; 0 when x_before2 is not usable */
    int quadratic;       /* the next first iterate from the last three solutions
                            (first_iterate_order) */
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
                            than IDLE_REFRESH_CONTRACTION (refresh() renews it) */
    int jacobian_only;   /* refresh(): single_step stops at its Jacobian */

    /* planar problem: frames are rotations about z by an angle phi (d3 at phi from +x) */
    double *phi0;      /* (nodes) rad, start of the step */
    double *phi1;      /* (nodes) rad, end of the step, for the iterate x */
    double *phi_th;    /* (nodes) rad, at the theta point */

    /* analytic_jacobian's scratch */
    double *jac_node;  /* (nodes x 18) d e / d omega at the end and at the theta point */
    double *jac_seg;   /* (nodes x 36) d d3 and d M of a segment / d omega of its two nodes */
} implicit_work;

static void destroy(void *p)
{
    implicit_work *w = p;
    if (!w) return;
    double **arrays[] = {&w->x, &w->dx, &w->x_last, &w->x_before, &w->x_before2, &w->residual, &w->eval_x, &w->perturbed, &w->band,
                         &w->frame0, &w->omega0, &w->vel0, &w->vel1, &w->d3mid0, &w->moment0,
                         &w->tipf0, &w->tipm0, &w->frame1, &w->frame_th, &w->darboux1,
                         &w->mid1, &w->d3mid1, &w->moment1, &w->save_frame, &w->save_pos, &w->save_vel,
                         &w->save_omega, &w->save_force, &w->phi0, &w->phi1, &w->phi_th,
                         &w->point_force, &w->point_moment, &w->vbar,
                         &w->pos0, &w->surface_force, &w->start_gap, &w->band_smooth,
                         &w->velocity_jac, &w->trail_jac, &w->jac_node, &w->jac_seg};
    for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; k++) free(*arrays[k]);
    free(w->threaded);
    free(w->node_push);
    rod_self_contact_destroy(w->self);
    free(w->touched);
    free(w->trail_touched);
    free(w->pivot);
    free(w->inv_diag);
    free(w->rows);
    free(w->lower);
    free(w->upper);
    free(w);
}

static const char *const end_names[2] = {"root", "tip"};

/* Reads one end's condition; -1 with a message when the scheme cannot model it. */
static int read_end(end_condition *e, int which, rod_end_kind kind, const double slide[3],
                    int twist_held, const rod_path *path, char *err, size_t errlen)
{
    memset(e, 0, sizeof *e);
    double len = v3_norm(slide);
    if (kind == ROD_END_FREE) {
        if (len > 0.0 || path) {
            snprintf(err, errlen, "implicit scheme: the %s is free, so it cannot %s; make it "
                     "pinned or clamped (ends.%s)", end_names[which],
                     path ? "follow a path (ends.*_motion)" : "slide (ends.*_slide)", end_names[which]);
            return -1;
        }
        return 0;
    }
    if (!isfinite(len) || (len > 0.0 && path)) {
        snprintf(err, errlen, "implicit scheme: the %s either slides (ends.%s_slide, a finite "
                 "direction) or follows a path (ends.%s_motion), not both", end_names[which],
                 end_names[which], end_names[which]);
        return -1;
    }
    e->held = 1;
    e->path = path;
    if (len > 0.0) {
        e->sliding = 1;
        v3_scale(e->slide, slide, 1.0 / len);
    }
    if (kind == ROD_END_CLAMPED) {
        if (e->sliding) { /* d3 along the slide; it may twist, unless held (ends.*_twist) */
            e->hold_omega[0] = e->hold_omega[1] = 1;
            e->hold_omega[2] = twist_held;
        }
        else e->clamped = 1;
    } else if (which == 0) {
        e->hold_omega[2] = 1; /* a pinned root is a torsion stop (rod.h) */
    }
    return 0;
}

static int vector_zero(const double a[3]) { return a[0] == 0.0 && a[1] == 0.0 && a[2] == 0.0; }

static void *create(const rod_model *m, char *err, size_t errlen)
{
    end_condition ends[2];
    if (read_end(&ends[0], 0, m->root_end, m->root_slide, m->slide_twist_held[0], m->root_motion,
                 err, errlen) ||
        read_end(&ends[1], 1, m->tip_end, m->tip_slide, m->slide_twist_held[1], m->tip_motion,
                 err, errlen))
        return NULL;
    int twist_held = ends[0].clamped || ends[0].hold_omega[2] || ends[1].clamped ||
                     ends[1].hold_omega[2];
    if (!twist_held && !(m->rotary_inertia[2] > 0.0)) {
        /* nothing resists a rigid turn of the rod about its own axis */
        static const char *const kinds[] = {"clamped", "pinned", "free"};
        snprintf(err, errlen, "implicit scheme: with ends root = %s%s, tip = %s%s nothing holds the "
                 "rod's twist, so it needs torsional inertia (physics.twist = 1 and "
                 "physics.rotary_inertia = 1), or an end clamped in place or a pinned root",
                 kinds[m->root_end], ends[0].sliding ? " (sliding)" : "", kinds[m->tip_end],
                 ends[1].sliding ? " (sliding)" : "");
        return NULL;
    }
    implicit_work *w = calloc(1, sizeof *w);
    if (!w) goto oom;
    size_t n = (size_t)m->nodes;
    memcpy(w->ends, ends, sizeof ends);
    w->nodes = m->nodes;
    /* the planar path models today's cantilever only: the new ends, curvature,
     * point loads, moments and starting states are 3-D here */
    int plain = ends[0].clamped && !ends[0].path && m->tip_end == ROD_END_FREE &&
                vector_zero(m->intrinsic_curvature) && m->point_load_count == 0 &&
                vector_zero(m->distributed_moment) && !m->initial_shape &&
                m->initial_velocity[2] == 0.0 && m->direction[2] == 0.0 &&
                m->surface_count == 0 && m->puncture_count == 0;
    w->planar = m->physics.planar && rod_model_loads_planar(m) && plain;
    w->distributed_moment = !vector_zero(m->distributed_moment);
    w->first = (w->planar || ends[0].clamped) ? 1 : 0;
    w->blocks = m->nodes - w->first;
    w->block = w->planar ? BLOCK_PLANAR : BLOCK;
    w->kl = w->planar ? BAND_PLANAR : BAND;
    /* punctures can be made by the needle during the run: a driven tip with
     * a needle and a tissue surface make room for them from the start */
    int tissue = 0;
    for (int k = 0; k < m->surface_count; k++) tissue |= m->surfaces[k].tissue;
    w->reach = (m->puncture_count > 0 || (tissue && m->needle_radius > 0.0)) ? 2 : 1;
    if (w->reach == 2) w->kl = BAND_PUNCTURE;
    w->contact = m->surface_count > 0 || w->reach == 2;
    w->needle_tissue = tissue && m->needle_radius > 0.0;
    static const int kinds3[BLOCK] = {0, 0, 0, 2, 2, 2};
    static const int kinds2[BLOCK_PLANAR] = {0, 0, 1, 1, 2};
    memcpy(w->var_kind, w->planar ? kinds2 : kinds3, (size_t)w->block * sizeof(int));
    w->unknowns = w->block * w->blocks;
    w->ldab = 3 * w->kl + 1; /* 2 kl + ku + 1: U gains kl diagonals by pivoting */
    w->max_reach = w->reach;
    size_t u = (size_t)w->unknowns;
    w->x = calloc(u, sizeof(double));
    w->dx = calloc(u, sizeof(double));
    w->residual = calloc(u, sizeof(double));
    w->eval_x = calloc(u, sizeof(double));
    w->x_last = calloc(u, sizeof(double));
    w->x_before = calloc(u, sizeof(double));
    w->x_before2 = calloc(u, sizeof(double));
    w->perturbed = calloc(u, sizeof(double));
    w->band = calloc((size_t)w->ldab * u, sizeof(double));
    w->pivot = calloc(u, sizeof *w->pivot);
    w->inv_diag = calloc(u, sizeof(double));
    w->lower = calloc(u, sizeof(int));
    w->upper = calloc(u, sizeof(int));
    if (w->contact) {
        w->band_smooth = calloc((size_t)w->ldab * u, sizeof(double));
        w->velocity_jac = calloc(n * 27, sizeof(double));
        w->touched = calloc(n, 1);
        w->trail_jac = calloc(n * 27, sizeof(double));
        w->trail_touched = calloc(n, 1);
        if (!w->band_smooth || !w->velocity_jac || !w->touched || !w->trail_jac ||
            !w->trail_touched)
            goto oom;
    }
    w->frame0 = calloc(n * 9, sizeof(double));
    w->omega0 = calloc(n * 3, sizeof(double));
    w->vel0 = calloc(n * 3, sizeof(double));
    w->vel1 = calloc(n * 3, sizeof(double));
    if (!w->vel1) goto oom;
    w->d3mid0 = calloc(n * 3, sizeof(double));
    w->moment0 = calloc(n * 3, sizeof(double));
    w->tipf0 = calloc(3, sizeof(double));
    w->tipm0 = calloc(3, sizeof(double));
    w->frame1 = calloc(n * 9, sizeof(double));
    w->frame_th = calloc(n * 9, sizeof(double));
    w->darboux1 = calloc(n * 3, sizeof(double));
    w->mid1 = calloc(n * 9, sizeof(double));
    w->d3mid1 = calloc(n * 3, sizeof(double));
    w->moment1 = calloc(n * 3, sizeof(double));
    w->save_frame = calloc(n * 9, sizeof(double));
    w->save_pos = calloc(n * 3, sizeof(double));
    w->save_vel = calloc(n * 3, sizeof(double));
    w->save_omega = calloc(n * 3, sizeof(double));
    w->save_force = calloc(n * 3, sizeof(double));
    w->phi0 = calloc(n, sizeof(double));
    w->phi1 = calloc(n, sizeof(double));
    w->phi_th = calloc(n, sizeof(double));
    w->jac_node = calloc(n * 18, sizeof(double));
    w->jac_seg = calloc(n * 36, sizeof(double));
    if (!w->jac_node || !w->jac_seg) goto oom;
    w->vbar = calloc(n * 3, sizeof(double));
    w->pos0 = calloc(n * 3, sizeof(double));
    w->surface_force = calloc(n * 3, sizeof(double));
    w->threaded = calloc(n, sizeof(unsigned));
    if (!w->threaded) goto oom;
    w->surface_count = m->surface_count;
    if (m->surface_count > 0) {
        w->start_gap = calloc(n * (size_t)m->surface_count * 7, sizeof(double));
        if (!w->start_gap) goto oom;
    }
    /* the finite differences never see contact (its part of the Jacobian is
     * in closed form: add_contact_jacobian), so friction's steep turn within
     * its creep speed does not ask for a smaller step */
    w->fd_step = 1e-7;
    w->surfaces = m->surfaces;
    if (!w->pos0 || !w->surface_force) goto oom;
    if (m->self_contact && !w->planar) {
        w->self = rod_self_contact_create(m->nodes, w->unknowns, w->first, BLOCK, m->diameter,
                                          m->ds, m->self_friction);
        w->node_push = calloc(n, sizeof(double));
        /* a multiple of 32 bytes (aligned_alloc's size must be one of the
         * alignment) */
        w->rows = aligned_alloc(32, (size_t)w->unknowns * ROWS_CHUNK * sizeof(double));
        if (!w->self || !w->node_push || !w->rows) goto oom;
    }
    if (!w->phi0 || !w->phi1 || !w->phi_th || !w->vbar) goto oom;
    double point_peak = 0.0, point_moment_peak = 0.0;
    if (m->point_load_count > 0) {
        w->point_force = calloc(n * 3, sizeof(double));
        w->point_moment = calloc(n * 3, sizeof(double));
        if (!w->point_force || !w->point_moment) goto oom;
        for (int k = 0; k < m->point_load_count; k++) {
            const rod_point_load *pl = &m->point_loads[k];
            if (pl->node < 0 || pl->node >= m->nodes) {
                snprintf(err, errlen, "implicit scheme: point load %d is at node %d; nodes are "
                         "0..%d", k + 1, pl->node, m->nodes - 1);
                destroy(w);
                return NULL;
            }
            v3_axpy(&w->point_force[3 * pl->node], 1.0, pl->force);
            v3_axpy(&w->point_moment[3 * pl->node], 1.0, pl->moment);
            point_peak = fmax(point_peak, v3_norm(pl->force));
            point_moment_peak = fmax(point_moment_peak, v3_norm(pl->moment));
        }
    }
    if (!w->x || !w->dx || !w->x_last || !w->x_before || !w->x_before2 || !w->residual || !w->eval_x || !w->perturbed || !w->band || !w->pivot || !w->inv_diag || !w->lower || !w->upper ||
        !w->frame0 || !w->omega0 || !w->vel0 || !w->d3mid0 || !w->moment0 || !w->tipf0 ||
        !w->tipm0 || !w->frame1 || !w->frame_th || !w->darboux1 || !w->mid1 || !w->d3mid1 || !w->moment1 ||
        !w->save_frame || !w->save_pos || !w->save_vel || !w->save_omega || !w->save_force)
        goto oom;

    /* Scales: the largest of the applied loads and the rod's own elastic
     * force EI/L^2, so that an unloaded rod still has a sensible scale. */
    double L = m->length, EI = m->stiffness[0];
    double fpeak = 0.0, mmax = 0.0;
    if (m->profile.kind == ROD_PROFILE_TABLE && m->profile.table.columns == 7) {
        const rod_table *t = &m->profile.table;
        for (int r = 0; r < t->rows; r++)
            for (int k = 0; k < 3; k++) {
                fpeak = fmax(fpeak, fabs(t->data[r * 7 + 1 + k]));
                mmax = fmax(mmax, fabs(t->data[r * 7 + 4 + k]));
            }
    } else {
        double scale = 1.0;
        if (m->profile.kind == ROD_PROFILE_TABLE)
            for (int r = 0; r < m->profile.table.rows; r++)
                scale = fmax(scale, fabs(m->profile.table.data[2 * r + 1]));
        fpeak = scale * v3_norm(m->tip_force);
        mmax = scale * v3_norm(m->tip_moment);
    }
    double q = v3_norm(m->distributed_force) * L; /* N/m over the length */
    fpeak = fmax(fpeak, point_peak);
    mmax = fmax(fmax(mmax, point_moment_peak), v3_norm(m->distributed_moment) * L);
    w->force_scale = fmax(fmax(EI / (L * L), fpeak), fmax(mmax / L, q));
    w->moment_scale = w->force_scale * L;
    double f1 = rod_first_bending_frequency(m);
    w->var_scale[0] = w->force_scale;
    w->var_scale[1] = 2.0 * M_PI * f1 * L * 1e-3;
    w->var_scale[2] = 2.0 * M_PI * f1 * 1e-3;
    return w;
oom:
    snprintf(err, errlen, "implicit scheme: out of memory for %d nodes", m->nodes);
    destroy(w);
    return NULL;
}

/* Tip force and moment at time t in global components, given the tip frame. */
static void tip_load_global(const rod_model *m, double t, const double *tip_frame,
                            double force[3], double moment[3])
{
    double f[3], mo[3];
    rod_tip_load(m, t, f, mo);
    if (m->tip_frame == ROD_FRAME_DIRECTOR) {
        m3_mul_v(force, tip_frame, f);
        m3_mul_v(moment, tip_frame, mo);
    } else {
        v3_copy(force, f);
        v3_copy(moment, mo);
    }
}

/* Midpoint d3 and elastic moment M = Q_mid B u (global) for given frames. */
static void elastic_state(const rod_model *m, const double *frame, double *darboux, double *mid,
                          double *d3mid, double *moment)
{
    rod_darboux_from_frames(m, frame, darboux);
    rod_midpoint_frames(m, frame, darboux, mid);
    for (int j = 0; j + 1 < m->nodes; j++) {
        double bu[3];
        for (int k = 0; k < 3; k++)
            bu[k] = m->stiffness[k] * (darboux[3 * j + k] - m->intrinsic_curvature[k]); /* (3.4) */
        m3_mul_v(&moment[3 * j], &mid[9 * j], bu);
        if (d3mid) m3_column(&d3mid[3 * j], &mid[9 * j], 2);
    }
}

/* end_geometry's segment j, one at a time */
static inline __attribute__((always_inline)) void
end_geometry_segment(const rod_model *m, const double *frame, int j, double *darboux,
                     double *d3mid, double *moment)
{
    const double inv_ds = 1.0 / m->ds;
    double rel[9], phi[3], half[3], bu[3], e3[3] = {0.0, 0.0, 1.0}, local[3];
    const double *q = &frame[9 * j];
    m3_mul_tn(rel, q, &frame[9 * (j + 1)]);
    m3_log(phi, rel);
    for (int k = 0; k < 3; k++) {
        darboux[3 * j + k] = phi[k] * inv_ds;
        half[k] = 0.5 * phi[k];
        bu[k] = m->stiffness[k] * (darboux[3 * j + k] - m->intrinsic_curvature[k]);
    }
    v3_rotate(local, half, e3);
    m3_mul_v(&d3mid[3 * j], q, local);
    v3_rotate(local, half, bu);
    m3_mul_v(&moment[3 * j], q, local);
}

/* The same as elastic_state for the end of the step, without forming the
 * midpoint frames Q_{i+1/2} = Q_i exp(h), h = ds/2 u: only d3 = Q_i exp(h) e3
 * and M = Q_i exp(h) B u are needed, each one rotation of a vector (the
 * residual evaluates this twice or more per step). LANES segments at a time
 * (base/vec3_lanes.h; the same numbers), one at a time where a segment turns
 * too far for the series and at the end: suture.ini 0.3x the time of this
 * loop one at a time with AVX2, 0.55x without. */
LANES_TARGET static void end_geometry(const rod_model *m, const double *frame, double *darboux,
                                      double *d3mid, double *moment)
{
    const double inv_ds = 1.0 / m->ds;
    const int segments = m->nodes - 1;
    int j = 0;
    for (; j + LANES <= segments; j += LANES) {
        lanes q[9], next[9], rel[9], phi[3], half[3], bu[3], dar[3], local[3], t;
        lanes_load9(q, frame, j, 9);
        lanes_load9(next, frame, j + 1, 9);
        lanes_mul_tn(rel, q, next);
        int series = lanes_log(phi, rel);
        if (series) {
            for (int k = 0; k < 3; k++) {
                dar[k] = phi[k] * inv_ds;
                half[k] = 0.5 * phi[k];
                bu[k] = m->stiffness[k] * (dar[k] - m->intrinsic_curvature[k]);
            }
            series = lanes_exp_in_series(half, &t);
        }
        if (!series) {
            for (int l = 0; l < LANES; l++) end_geometry_segment(m, frame, j + l, darboux, d3mid, moment);
            continue;
        }
        const lanes zero = {0.0}, one = zero + 1.0;
        const lanes e3[3] = {zero, zero, one};
        lanes d3[3], mo[3];
        lanes_rotate(local, half, &t, e3);
        lanes_mul_v(d3, q, local);
        lanes_rotate(local, half, &t, bu);
        lanes_mul_v(mo, q, local);
        lanes_store3(darboux, j, 3, dar);
        lanes_store3(d3mid, j, 3, d3);
        lanes_store3(moment, j, 3, mo);
    }
    for (; j < segments; j++) end_geometry_segment(m, frame, j, darboux, d3mid, moment);
}

static inline const double *block_force(const implicit_work *w, const double *x, int b)
{
    return &x[BLOCK * (b - w->first)]; /* N_{b-1/2}, b >= 1 */
}
static inline const double *block_omega(const implicit_work *w, const double *x, int b)
{
    return &x[BLOCK * (b - w->first) + 3]; /* omega_b, b >= first */
}

/* The moment (3.6)_2 balances over the cell of node b, global: the
 * theta-weighted elastic moments of the segments beside it and the arms
 * ds/2 d3 x N of their contact forces (the tip moment at the tip), the
 * distributed and point moments. d3l and d3r get the theta-weighted d3 of
 * the segments left and right of it (unset when there is none). */
static inline __attribute__((always_inline)) void
cell_moment(const implicit_work *w, const rod_model *m, const double *x, int b,
            const double tipm[3], const int left, const int right, double total[3],
            double d3l[3], double d3r[3])
{
    const int j = b - 1;
    const double theta = m->options.theta, ds = m->ds;
    const double wb = (left && right) ? ds : 0.5 * ds;
    double cr[3];
    if (right) {
        const double *n_right = block_force(w, x, b + 1);
        for (int k = 0; k < 3; k++) {
            total[k] = theta * w->moment1[3 * b + k] + (1.0 - theta) * w->moment0[3 * b + k];
            d3r[k] = theta * w->d3mid1[3 * b + k] + (1.0 - theta) * w->d3mid0[3 * b + k];
        }
        v3_cross(cr, d3r, n_right);
        v3_axpy(total, 0.5 * ds, cr);
    } else {
        v3_copy(total, tipm);
    }
    if (left) {
        const double *n_left = block_force(w, x, b);
        for (int k = 0; k < 3; k++) {
            total[k] -= theta * w->moment1[3 * j + k] + (1.0 - theta) * w->moment0[3 * j + k];
            d3l[k] = theta * w->d3mid1[3 * j + k] + (1.0 - theta) * w->d3mid0[3 * j + k];
        }
        v3_cross(cr, d3l, n_left);
        v3_axpy(total, 0.5 * ds, cr);
    }
    if (w->distributed_moment) v3_axpy(total, wb, m->distributed_moment);
    if (w->point_moment) v3_axpy(total, w->point_factor, &w->point_moment[3 * b]);
}

/* (3.6)_2 over the cell of node b for the angular velocity om at the end of
 * the step (director components): writes the unscaled residual (N m) that a
 * support's moment would balance. The frames and moments at the end of the
 * step are those of the current residual evaluation. */
static inline __attribute__((always_inline)) void
angular_balance(const implicit_work *w, const rod_model *m, const double *x, int b, double dt,
                const double tipm[3], const double *frame_th, const double om[3], double raw[3],
                const int left, const int right)
{
    const double theta = m->options.theta, ds = m->ds;
    const double wb = (left && right) ? ds : 0.5 * ds;
    double total[3], d3l[3], d3r[3];
    cell_moment(w, m, x, b, tipm, left, right, total, d3l, d3r);
    double body[3], wbar[3], iw[3], gyro[3];
    m3_mul_tv(body, &frame_th[9 * b], total);
    const double *inertia = m->rotary_inertia, inv_dt = 1.0 / dt;
    for (int k = 0; k < 3; k++) {
        wbar[k] = theta * om[k] + (1.0 - theta) * w->omega0[3 * b + k];
        iw[k] = inertia[k] * wbar[k];
    }
    v3_cross(gyro, wbar, iw);
    for (int k = 0; k < 3; k++) {
        double inertial = wb * (inertia[k] * (om[k] - w->omega0[3 * b + k]) * inv_dt + gyro[k]);
        raw[k] = inertial - body[k] + wb * m->angular_damping * wbar[k];
    }
}

/* Q(t+dt) = Q(t) exp(dt omega_bar) and the theta-point frame of node i, the
 * held components of omega (mask, or NULL) left out. */
static inline __attribute__((always_inline)) void
advance_frame(implicit_work *w, const double *x, int i, double dt, double theta, const int *held)
{
    double wbar[3], rot[9];
    const double *om = block_omega(w, x, i);
    for (int k = 0; k < 3; k++)
        wbar[k] = dt * (theta * om[k] + (1.0 - theta) * w->omega0[3 * i + k]);
    if (held)
        for (int k = 0; k < 3; k++)
            if (held[k]) wbar[k] = 0.0;
    m3_exp(rot, wbar);
    m3_mul(&w->frame1[9 * i], &w->frame0[9 * i], rot);
    if (theta < 1.0) {
        v3_scale(wbar, wbar, theta);
        m3_exp(rot, wbar);
        m3_mul(&w->frame_th[9 * i], &w->frame0[9 * i], rot);
    }
}

/* advance_frame for the nodes lo .. hi - 1 (none held), LANES at a time
 * (base/vec3_lanes.h; the same numbers), one at a time where a node turns
 * too far within the step for the series and at the end */
LANES_TARGET static void advance_frames(implicit_work *w, const double *x, int lo, int hi,
                                        double dt, double theta)
{
    int i = lo;
    for (; i + LANES <= hi; i += LANES) {
        lanes om[3], om0[3], wbar[3], rot[9], q0[9], q1[9], t;
        lanes_load3(om, x + 3, i - w->first, BLOCK); /* block_omega */
        lanes_load3(om0, w->omega0, i, 3);
        for (int k = 0; k < 3; k++) wbar[k] = dt * (theta * om[k] + (1.0 - theta) * om0[k]);
        if (!lanes_exp_in_series(wbar, &t)) {
            for (int l = 0; l < LANES; l++) advance_frame(w, x, i + l, dt, theta, NULL);
            continue;
        }
        lanes_exp(rot, wbar, &t);
        lanes_load9(q0, w->frame0, i, 9);
        lanes_mul(q1, q0, rot);
        lanes_store9(w->frame1, i, 9, q1);
        if (theta < 1.0) {
            for (int k = 0; k < 3; k++) wbar[k] = wbar[k] * theta;
            lanes_exp_in_series(wbar, &t); /* smaller: within the series */
            lanes_exp(rot, wbar, &t);
            lanes_mul(q1, q0, rot);
            lanes_store9(w->frame_th, i, 9, q1);
        }
    }
    for (; i < hi; i++) advance_frame(w, x, i, dt, theta, NULL);
}

/* An end node's velocity at the end of the step and its mean over the
 * step (global): its cell's (3.3)_1 when free, the path's when held,
 * projected on the slide when sliding. `applied` gets the cell's load
 * (contact forces, distributed and point loads), N. */
static void end_velocity(implicit_work *w, const rod_model *m, const end_condition *e, int b,
                         const double n_left[3], const double n_right[3], double dt,
                         double applied[3])
{
    const double theta = m->options.theta, wb = 0.5 * m->ds, c = m->linear_damping;
    const double mass = m->mass_per_length;
    for (int k = 0; k < 3; k++) applied[k] = n_right[k] - n_left[k] + wb * m->distributed_force[k];
    if (w->point_force) v3_axpy(applied, w->point_factor, &w->point_force[3 * b]);
    double *v1 = &w->vel1[3 * b], *vb = &w->vbar[3 * b];
    const double *v0 = &w->vel0[3 * b];
    if (e->held && !e->sliding) {
        v3_copy(v1, e->vel1);
        v3_copy(vb, e->vbar);
        return;
    }
    const double inv_coeff = 1.0 / (wb * (mass / dt + theta * c));
    for (int k = 0; k < 3; k++) {
        v1[k] = (wb * (mass / dt - (1.0 - theta) * c) * v0[k] + applied[k]) * inv_coeff;
        vb[k] = theta * v1[k] + (1.0 - theta) * v0[k];
    }
    if (e->sliding) { /* a sleeve: only the motion along it */
        v3_scale(v1, e->slide, v3_dot(v1, e->slide));
        v3_scale(vb, e->slide, v3_dot(vb, e->slide));
        v3_add(vb, vb, e->correction);
    }
}

/* d/de of e contact_fraction(e, floor): the fraction of a change of the
 * free offset that the contact force takes back (for its Jacobian). */
static inline double compliant_slope(double e, double floor)
{
    double kappa = CONTACT_STIFF + e / floor;
    return kappa / (1.0 + kappa) + (e / floor) / ((1.0 + kappa) * (1.0 + kappa));
}

/* The slopes of creep_speed's root sp(speed, c), from the implicit function
 * sp + c phi(sp / eps(c)) = speed: d sp / d speed and d sp / d c. */
static void creep_slopes(double c, double sp, double *d_speed, double *d_c)
{
    const double k = CONTACT_STIFF / c + 1.0 / CONTACT_CREEP_MAX, eps = 1.0 / k + CONTACT_CREEP;
    const double x = sp / eps, q = 1.0 + x * x, root = sqrt(q), slope = 1.0 / (q * root);
    const double deps_dc = CONTACT_STIFF / (c * c * k * k);
    const double g_sp = 1.0 + (c / eps) * slope;
    const double g_c = x / root - c * slope * (x / eps) * deps_dc;
    *d_speed = 1.0 / g_sp;
    *d_c = -g_c / g_sp;
}

/* How a swept contact's half-space turns with the node's velocity v
 * (surface_turn): the depth's gradient g (d e = (a / push) g.d v) and the
 * normal's Jacobian nn = d n / d v, with push lambda and vn = v'.n. */
typedef struct surface_turn {
    double g[3], nn[9], push_lambda, vn;
} surface_turn;

/* A node that did not touch at the step's start is held where its path
 * r0 -> r1 = r0 + dt vbar first enters the grown solid (node_contact), at
 * the fraction f, the point p = r0 + f D (D = r1 - r0) and the normal n
 * there. On a curved part (the Hessian H of the signed distance at p,
 * rod_surface_curvature) p and n turn with r1: with n.dp = 0, d p = f (I -
 * D n^T / n.D) d r1 = P d r1, d n = H P d r1, and the depth e = (r1 - p).n
 * has d e = g.d r1, g = n + (1 - f) (H P)^T D; d r1 / d v = a / push (a = dt
 * theta push). Returns 0 for a path grazing the solid (n.D above -1e-9 |D|),
 * where P is unbounded: n and p are then taken as fixed. */
static int surface_turn_of(surface_turn *turn, const double n[3], const double hessian[9],
                           const double d[3], double f, double a, double push, double lambda,
                           double vn)
{
    const double nd = v3_dot(n, d);
    if (!(nd < -1e-9 * v3_norm(d))) return 0;
    double proj[9], hp[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) proj[3 * i + j] = f * ((i == j) - d[i] * n[j] / nd);
    m3_mul(hp, hessian, proj);
    for (int k = 0; k < 9; k++) turn->nn[k] = (a / push) * hp[k];
    for (int j = 0; j < 3; j++) {
        turn->g[j] = n[j];
        for (int i = 0; i < 3; i++) turn->g[j] += (1.0 - f) * hp[3 * i + j] * d[i];
    }
    turn->push_lambda = push * lambda;
    turn->vn = vn;
    return 1;
}

/* Composes jac with the Jacobian of one surface's map in node_contact,
 * v -> v + push F(v) (normal n, the tangential velocity vt after the normal
 * force, its norm speed and the friction's sp = contact_creep_speed(speed, c),
 * c = push mu lambda; stiff = d(e kappa/(1+kappa))/de, compliant_slope):
 *   normal:   v' = v + push lambda n, d lambda / d v = -stiff / push g^T,
 *             so d v'/d v = A' = I - stiff n g^T + push lambda Nn; with the
 *             half-space held over the iteration (turn NULL: a node touching
 *             at the start, or a flat part) g = n and Nn = d n / d v = 0;
 *   friction: v'' = vn n + sp t (vn = v'.n, vt = v' - vn n = speed t), with
 *             d sp from creep_slopes and d c / d v = -mu stiff g^T:
 *             d v'' = fric A' - d_c mu stiff t g^T + ((1 - ratio) n v'^T +
 *             vn ((1 - ratio) I + (ratio - d_speed) t t^T)) Nn,
 *             fric = n n^T + ratio (I - n n^T - t t^T) + d_speed t t^T,
 *             ratio = sp / speed. */
static void surface_map_jacobian(double jac[9], const double n[3], const double vt[3],
                                 double speed, double sp, double c, double mu, double stiff,
                                 const surface_turn *turn)
{
    const double *g = turn ? turn->g : n;
    double map[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) map[3 * i + j] = (i == j) - stiff * n[i] * g[j];
    if (turn)
        for (int k = 0; k < 9; k++) map[k] += turn->push_lambda * turn->nn[k];
    if (c > 0.0) {
        /* at speed 0 (a node pressed straight in) the limit: sp / speed ->
         * d sp / d speed, no direction t */
        double t[3] = {0.0, 0.0, 0.0}, d_speed, d_c, fric[9];
        if (speed > 0.0) v3_scale(t, vt, 1.0 / speed);
        creep_slopes(c, sp, &d_speed, &d_c);
        const double ratio = speed > 0.0 ? sp / speed : d_speed;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                fric[3 * i + j] = n[i] * n[j] + ratio * ((i == j) - n[i] * n[j] - t[i] * t[j]) +
                                  d_speed * t[i] * t[j];
        m3_mul(map, fric, map);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) map[3 * i + j] -= d_c * mu * stiff * t[i] * g[j];
        if (turn) {
            double vp[3], side[9], extra[9];
            const double vn = turn->vn;
            for (int k = 0; k < 3; k++) vp[k] = vt[k] + vn * n[k];
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    side[3 * i + j] = (1.0 - ratio) * n[i] * vp[j] +
                                      vn * ((1.0 - ratio) * (i == j) + (ratio - d_speed) * t[i] * t[j]);
            m3_mul(extra, side, turn->nn);
            for (int k = 0; k < 9; k++) map[k] += extra[k];
        }
    }
    m3_mul(jac, map, jac);
}

/* Contact of node b with the surfaces (issue 11), inside the residual.
 *
 * The velocity is not a Newton unknown: (3.3)_1 gives it from N, and a
 * contact force F at the node changes it by push F (push = 1 / (w_b (m/dt +
 * theta c)), the node's compliance), so the end of the step moves by a F,
 * a = dt theta push. Given the iterate's N, the node's contact is a problem
 * of its own, solved here in closed form:
 *   - normal: where the free motion would end a depth e inside the surface
 *     grown by the rod's radius, the force along the outward normal that
 *     takes back the fraction kappa / (1 + kappa) of it (compliant_fraction:
 *     an implicit spring; what is left is below 1 % of the radius), else 0;
 *   - friction: regularised Coulomb against the end-of-step tangential
 *     velocity, limited by mu times the normal force (contact_creep_speed).
 * The contact force depends on the node's own N only, like v: the
 * Jacobian's band and colouring are unchanged. The residual is piecewise
 * smooth where a contact switches on; Newton takes a line search then.
 *
 * No tunnelling: a node that was clear of the surface (by more than a tenth
 * of the radius) is held by the half-space where its straight path over the
 * step enters the grown solid (rod_surface_sweep), so a node that would
 * cross a thin pad within a step stops at its entry face; a node touching at
 * the start is held by the half-space tangent at its nearest point. Only nodes carry contact: a segment over a box's edge can cut
 * it by up to ds^2 / (8 R) for the rounding R of the grown edge, here the
 * rod's radius (README). Nodes threaded through tissue between punctures
 * skip that surface (prepare_punctures). */
static void node_contact(implicit_work *w, const rod_model *m, int b, double push, double dt)
{
    double *v1 = &w->vel1[3 * b], *vb = &w->vbar[3 * b], *force = &w->surface_force[3 * b];
    const double *r0 = &w->pos0[3 * b];
    const double theta = m->options.theta, grow = 0.5 * m->diameter, a = dt * theta * push;
    v3_set(force, 0.0, 0.0, 0.0);
    /* want_jacobian: jac = d v1 / d (v1 on entry), composed over the surfaces */
    double jac[9] = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
    /* a second pass only when two surfaces act on the node (a corner): one
     * surface's correction may push it into the other */
    int active = 0;
    for (int pass = 0; pass < 2 && (pass == 0 || active > 1); pass++)
        for (int j = 0; j < w->surface_count; j++) {
            const rod_surface *sf = &w->surfaces[j];
            if (w->threaded[b] & (1u << j)) continue;
            double r1[3], n[3], p[3], step[3];
            for (int k = 0; k < 3; k++) {
                step[k] = dt * vb[k];
                r1[k] = r0[k] + step[k];
            }
            const double *start = &w->start_gap[7 * ((size_t)b * (size_t)w->surface_count + (size_t)j)];
            const double gap0 = start[0], *n0 = start + 1, *near0 = start + 4;
            double depth, hit = 0.0, hessian[9];
            int curved = 0; /* the sweep entered a curved part: p and n turn with v */
            if (gap0 <= 0.1 * grow) {
                /* touching at the start: the half-space tangent at the start's
                 * nearest point, fixed over the step, so the depth is linear
                 * in the iterate (no switch between a box's faces at its
                 * edges while Newton iterates); a node sliding along a curved
                 * surface is left outside by (v dt)^2 / 2R, taken back by the
                 * next step */
                v3_copy(n, n0);
                v3_copy(p, near0);
                double d[3];
                v3_sub(d, r1, p);
                depth = v3_dot(d, n);
            } else {
                /* the gap is 1-Lipschitz: a path shorter than the start's gap
                 * cannot reach the solid (the sweep's own first test, without
                 * its two gap evaluations) */
                if (gap0 > v3_norm(step)) continue;
                if (!rod_surface_sweep(sf, r0, r1, grow, &hit, p, n)) continue;
                double d[3];
                v3_sub(d, r1, p);
                depth = v3_dot(d, n);
                curved = w->want_jacobian && depth < 0.0 && rod_surface_curvature(sf, p, n, grow, hessian);
            }
            if (!(depth < 0.0)) continue;
            active++;
            double lambda = -depth / a * contact_fraction(-depth, 0.01 * grow), fn[3], vt[3];
            v3_scale(fn, n, lambda);
            v3_axpy(v1, push, fn);
            v3_axpy(vb, theta * push, fn);
            v3_axpy(force, 1.0, fn);
            /* friction against the tangential velocity (contact_creep_speed) */
            double vn = v3_dot(v1, n);
            for (int k = 0; k < 3; k++) vt[k] = v1[k] - vn * n[k];
            double speed = v3_norm(vt), limit = sf->friction * lambda, ft[3], sp = speed;
            if (speed > 0.0 && limit > 0.0) {
                sp = contact_creep_speed(speed, push * limit);
                v3_scale(ft, vt, -(speed - sp) / (push * speed));
                v3_axpy(v1, push, ft);
                v3_axpy(vb, theta * push, ft);
                v3_axpy(force, 1.0, ft);
            }
            if (w->want_jacobian) {
                surface_turn turn;
                const int turning = curved && surface_turn_of(&turn, n, hessian, step, hit, a, push,
                                                              lambda, vn);
                surface_map_jacobian(jac, n, vt, speed, sp, push * limit, sf->friction,
                                     compliant_slope(-depth, 0.01 * grow), turning ? &turn : NULL);
            }
        }
    if (w->want_jacobian && active) {
        double *d = &w->velocity_jac[27 * b];
        memset(d, 0, 27 * sizeof(double));
        memcpy(d + 9, jac, sizeof jac);
        w->touched[b] = 1;
    }
}

/* Each node's gap, normal and nearest point on each surface at the start
 * of the step (node_contact reads them in every residual evaluation). */
static void prepare_contact(implicit_work *w, const rod_model *m)
{
    const double grow = 0.5 * m->diameter;
    for (int b = 0; b < w->nodes; b++)
        for (int j = 0; j < w->surface_count; j++) {
            double *start = &w->start_gap[7 * ((size_t)b * (size_t)w->surface_count + (size_t)j)];
            start[0] = rod_surface_gap(&w->surfaces[j], &w->pos0[3 * b], grow, start + 1, start + 4);
        }
}

/* Marks node b's velocity map as recorded, from the identity if it was not. */
static void touch_node(implicit_work *w, int b)
{
    if (w->touched[b]) return;
    double *d = &w->velocity_jac[27 * b];
    memset(d, 0, 27 * sizeof(double));
    d[9] = d[13] = d[17] = 1.0;
    w->touched[b] = 1;
}

/* One puncture's map in puncture_forces, for its Jacobian. */
typedef struct puncture_map {
    int j;                   /* segment j..j+1 */
    double wj, wk;           /* the point's weights on nodes j, j+1 */
    double pj, pk, peff;     /* the nodes' and the point's compliance, m/s per N */
    double dt_theta;         /* s */
    const double *t;         /* (3) the thread's direction */
    const double *f;         /* (3) the force across, N */
    double across;           /* |f|, N */
    double mu, vt, sp;       /* friction; the point's velocity along t (after f) and
                                creep_speed's root, m/s */
} puncture_map;

/* Composes node j's and j+1's velocity maps with one puncture's: z = (v_j,
 * v_j+1) -> z + (pj wj, pk wk) (f + ft t), differentiated as in
 * puncture_forces: d e / d z = dt theta (wj, wk) (I - t t^T), d f / d e
 * given; the friction ft = -(|vt| - sp) sign(vt) / peff with d vt / d z =
 * (wj, wk) t^T (f is across t), d sp from creep_slopes and d c = peff mu
 * d|f|. A node's map keeps its neighbours' columns only: a second puncture on
 * the next segment would reach two nodes on, beyond the band (left out). */
static void puncture_map_jacobian(implicit_work *w, const puncture_map *p, const double df_de[9])
{
    const double *t = p->t, g[2] = {p->pj * p->wj, p->pk * p->wk}, wz[2] = {p->wj, p->wk};
    double fz[18], m6[36];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            double ap = 0.0; /* (d f / d e) (I - t t^T) */
            for (int l = 0; l < 3; l++) ap += df_de[3 * r + l] * ((l == c) - t[l] * t[c]);
            for (int q = 0; q < 2; q++) fz[6 * r + 3 * q + c] = ap * p->dt_theta * wz[q];
        }
    for (int r = 0; r < 6; r++)
        for (int c = 0; c < 6; c++) m6[6 * r + c] = (r == c) + g[r / 3] * fz[6 * (r % 3) + c];
    const double c_limit = p->peff * p->mu * p->across;
    if (c_limit > 0.0) { /* at speed 0 too: sp has the slope d_speed there */
        double d_speed, d_c, dft[6];
        creep_slopes(c_limit, p->sp, &d_speed, &d_c);
        const double sign = p->vt > 0.0 ? 1.0 : -1.0;
        for (int c = 0; c < 6; c++) {
            double dvt = wz[c / 3] * t[c % 3], dacross = 0.0;
            for (int r = 0; r < 3; r++) dacross += p->f[r] / p->across * fz[6 * r + c];
            double dsp = d_speed * sign * dvt + d_c * p->peff * p->mu * dacross;
            dft[c] = -(dvt - sign * dsp) / p->peff;
        }
        for (int r = 0; r < 6; r++)
            for (int c = 0; c < 6; c++) m6[6 * r + c] += g[r / 3] * t[r % 3] * dft[c];
    }
    /* rows of nodes j and j+1 over the columns of nodes j-1 .. j+2 */
    const int j = p->j;
    touch_node(w, j);
    touch_node(w, j + 1);
    double rows[2][3][12], out[2][3][12];
    memset(rows, 0, sizeof rows);
    for (int q = 0; q < 2; q++)
        for (int blk = 0; blk < 3; blk++)
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++)
                    rows[q][r][3 * (blk + q) + c] = w->velocity_jac[27 * (j + q) + 9 * blk + 3 * r + c];
    for (int q = 0; q < 2; q++)
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 12; c++) {
                double sum = 0.0;
                for (int l = 0; l < 6; l++) sum += m6[6 * (3 * q + r) + l] * rows[l / 3][l % 3][c];
                out[q][r][c] = sum;
            }
    for (int q = 0; q < 2; q++)
        for (int blk = 0; blk < 3; blk++)
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++)
                    w->velocity_jac[27 * (j + q) + 9 * blk + 3 * r + c] = out[q][r][3 * (blk + q) + c];
}

/* The punctures' forces (issue 11), inside the residual, after every
 * node's velocity and surface contact: a sliding point constraint. The
 * thread's point at (segment j, fraction alpha) must pass through the
 * puncture's point P: the force across the thread (perpendicular to the
 * segment) that puts it there, short by 1 / (1 + CONTACT_STIFF) as the
 * surfaces' normal force, and Coulomb friction along the thread limited by
 * mu times that force (contact_creep_speed), so the tension drops across a
 * puncture by at most mu |F_across| while the thread slides through. The
 * force acts on the two nodes by the weights 1 - alpha, alpha; the point's
 * velocity responds with the compliance (1-alpha)^2 push_j + alpha^2
 * push_j+1. Where the thread passes is updated after each step
 * (update_punctures), so it slides through at whatever arc length. */
static void puncture_forces(implicit_work *w, const rod_model *m, double push, double dt)
{
    const int n = w->nodes;
    const double theta = m->options.theta;
    for (int k = 0; k < w->puncture_count; k++) {
        const int j = w->punct[k].j, i2 = j + 1;
        const double al = w->punct[k].alpha, *t = w->punct[k].tangent;
        double pj = (j == 0 || j == n - 1) ? 2.0 * push : push;
        double pk = (i2 == n - 1) ? 2.0 * push : push;
        const end_condition *ej = j == 0 ? &w->ends[0] : NULL;
        const end_condition *ek = i2 == n - 1 ? &w->ends[1] : NULL;
        if (ej && ej->held) pj = 0.0; /* a held end's velocity is its support's */
        if (ek && ek->held) pk = 0.0;
        const double wj = 1.0 - al, wk = al, peff = wj * wj * pj + wk * wk * pk;
        double *force = w->punct[k].force;
        v3_set(force, 0.0, 0.0, 0.0);
        /* at a held end's node the support holds the thread at the point */
        if (!(peff > 1e-6 * push)) continue;
        double rp[3], e[3], f[3];
        for (int c = 0; c < 3; c++)
            rp[c] = wj * (w->pos0[3 * j + c] + dt * w->vbar[3 * j + c]) +
                    wk * (w->pos0[3 * i2 + c] + dt * w->vbar[3 * i2 + c]);
        v3_sub(e, rp, w->punct[k].point);
        v3_axpy(e, -v3_dot(e, t), t);
        const double miss = v3_norm(e), floor = 0.005 * m->diameter;
        v3_scale(f, e, -contact_fraction(miss, floor) / (dt * theta * peff));
        for (int c = 0; c < 3; c++) {
            w->vel1[3 * j + c] += pj * wj * f[c];
            w->vbar[3 * j + c] += theta * pj * wj * f[c];
            w->vel1[3 * i2 + c] += pk * wk * f[c];
            w->vbar[3 * i2 + c] += theta * pk * wk * f[c];
        }
        v3_copy(force, f);
        /* friction along the thread */
        double across = v3_norm(f), limit = w->punct[k].friction * across, vt = 0.0;
        for (int c = 0; c < 3; c++) vt += t[c] * (wj * w->vel1[3 * j + c] + wk * w->vel1[3 * i2 + c]);
        double speed = fabs(vt), sp = speed;
        if (speed > 0.0 && limit > 0.0) {
            sp = contact_creep_speed(speed, peff * limit);
            double ft = -(speed - sp) / peff * (vt > 0.0 ? 1.0 : -1.0);
            for (int c = 0; c < 3; c++) {
                w->vel1[3 * j + c] += pj * wj * ft * t[c];
                w->vbar[3 * j + c] += theta * pj * wj * ft * t[c];
                w->vel1[3 * i2 + c] += pk * wk * ft * t[c];
                w->vbar[3 * i2 + c] += theta * pk * wk * ft * t[c];
                force[c] += ft * t[c];
            }
        }
        if (w->want_jacobian) {
            /* d f / d e = -(s I + s' e e^T / |e|), s = kappa/(1+kappa) / (dt theta peff) */
            const double scale = 1.0 / (dt * theta * peff), frac = contact_fraction(miss, floor);
            double df_de[9];
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++)
                    df_de[3 * r + c] = -scale * ((r == c) * frac +
                        (miss > 0.0 ? (compliant_slope(miss, floor) - frac) * e[r] * e[c] / (miss * miss) : 0.0));
            const puncture_map map = {j, wj, wk, pj, pk, peff, dt * theta, t, f, across,
                                      w->punct[k].friction, vt, sp};
            puncture_map_jacobian(w, &map, df_de);
        }
    }
}

/* Segment and fraction of each puncture for the step from the state, and
 * the thread's direction there (from the start of the step). */
static void prepare_punctures(implicit_work *w, const rod_model *m, const rod_state *s)
{
    const int n = w->nodes;
    w->puncture_count = s->puncture_count;
    for (int k = 0; k < s->puncture_count; k++) {
        double u = s->puncture[k].s / m->ds;
        int j = (int)floor(u);
        if (j > n - 2) j = n - 2;
        if (j < 0) j = 0;
        double al = u - j;
        w->punct[k].j = j;
        w->punct[k].alpha = al < 0.0 ? 0.0 : al > 1.0 ? 1.0 : al;
        v3_copy(w->punct[k].point, s->puncture[k].point);
        w->punct[k].friction = s->puncture[k].friction;
        /* the thread's direction at the point: the node tangents (central
         * differences) interpolated, not the segment's, so that the point can
         * slide along the thread when it sits at a node where the thread
         * turns (a tight bend at the puncture) */
        double t[3] = {0.0, 0.0, 0.0};
        for (int e = 0; e < 2; e++) {
            int i = j + e, lo = i > 0 ? i - 1 : 0, hi = i < n - 1 ? i + 1 : n - 1;
            double d[3];
            v3_sub(d, &s->position[3 * hi], &s->position[3 * lo]);
            v3_axpy(t, (e ? al : 1.0 - al) / v3_norm(d), d);
        }
        v3_scale(w->punct[k].tangent, t, 1.0 / v3_norm(t));
        v3_set(w->punct[k].force, 0.0, 0.0, 0.0);
    }
    /* the thread between a tissue surface's punctures is inside it (no
     * contact with that surface: rod_threaded_nodes) */
    rod_threaded_nodes(m, s, w->threaded);
    for (int j = 0; j < m->surface_count && j < 32; j++) {
        /* the thread within a needle radius of its tip follows the needle
         * into the hole its point cuts before the back (the tip) crosses the
         * surface, where the puncture is made: no contact with tissue there */
        if (w->needle_tissue && m->surfaces[j].tissue)
            for (int i = 0; i < n; i++)
                if (i * m->ds >= m->length - m->needle_radius - m->ds) w->threaded[i] |= 1u << j;
    }
}

/* After a step: where the thread near a needle-carrying driven tip (within
 * a needle radius of it: the part that follows the needle through the hole
 * its point cut) crosses a tissue surface at a point no puncture holds yet,
 * a puncture is made: at the thread's own crossing, so the thread passes
 * through it from the start. Returns -1 when there is no room for one more
 * (ROD_MAX_PUNCTURES). */
static int needle_punctures(const rod_model *m, rod_state *s, rod_report *report)
{
    const int n = m->nodes;
    const double reach = m->needle_radius + 2.0 * m->ds;
    for (int j = 0; j < m->surface_count && j < 32; j++) {
        const rod_surface *sf = &m->surfaces[j];
        if (!sf->tissue) continue;
        for (int i = n - 2; i >= 0 && (n - 1 - i) * m->ds <= reach; i--) {
            const double *a = &s->position[3 * i], *b = &s->position[3 * (i + 1)];
            double ga = rod_surface_gap(sf, a, 0.0, NULL, NULL);
            double gb = rod_surface_gap(sf, b, 0.0, NULL, NULL);
            if ((ga > 0.0) == (gb > 0.0)) continue;
            /* the crossing, by bisection along the segment */
            double lo = 0.0, hi = 1.0, point[3];
            for (int it = 0; it < 60; it++) {
                double mid = 0.5 * (lo + hi);
                for (int c = 0; c < 3; c++) point[c] = a[c] + mid * (b[c] - a[c]);
                if ((rod_surface_gap(sf, point, 0.0, NULL, NULL) > 0.0) == (ga > 0.0)) lo = mid;
                else hi = mid;
            }
            double f = 0.5 * (lo + hi);
            /* on the needle's own segment, not yet within NEEDLE_HOLE_CLEAR
             * of the held tip: the hole waits for the next step */
            if (i == n - 2 && f > NEEDLE_HOLE_CLEAR) continue;
            for (int c = 0; c < 3; c++) point[c] = a[c] + f * (b[c] - a[c]);
            int held = 0;
            for (int k = 0; k < s->puncture_count && !held; k++) {
                double d[3];
                v3_sub(d, s->puncture[k].point, point);
                held = s->puncture[k].surface == j && v3_norm(d) < 2.0 * m->ds;
            }
            if (held) continue;
            if (s->puncture_count >= ROD_MAX_PUNCTURES) {
                snprintf(report->message, sizeof report->message,
                         "implicit scheme: the needle went through the tissue surface of line "
                         "%d at t = %.6g s, but the run already holds %d punctures (the most); "
                         "shorten the needle's path (ends.tip_motion)", sf->line, s->time,
                         ROD_MAX_PUNCTURES);
                return -1;
            }
            rod_puncture_state *ps = &s->puncture[s->puncture_count++];
            memset(ps, 0, sizeof *ps);
            v3_copy(ps->point, point);
            ps->s = (i + f) * m->ds;
            ps->friction = sf->friction;
            ps->surface = j;
        }
    }
    return 0;
}

/* After a step: where the thread passes each puncture now (the nearest
 * point of the segments near the old one), and the force it exerts there. */
static void update_punctures(implicit_work *w, const rod_model *m, rod_state *s)
{
    for (int k = 0; k < s->puncture_count; k++) {
        rod_puncture_state *ps = &s->puncture[k];
        const int j0 = w->punct[k].j;
        ps->s = rod_nearest_arc_length_between(m, s->position, ps->point, j0 - 3, j0 + 3, NULL);
        v3_scale(ps->force, w->punct[k].force, -1.0);
    }
}

/* m: the farthest a node moves over the step of the last residual
 * evaluation (r(t+dt) = r(t) + dt vbar) */
static double largest_motion(const implicit_work *w, double dt)
{
    double moved = 0.0;
    for (int i = 0; i < w->nodes; i++) moved = fmax(moved, dt * v3_norm(&w->vbar[3 * i]));
    return moved;
}

/* Self-contact's data of a step (issue 12): each node's compliance over the
 * step and the candidate pairs closer than one diameter + margin at its
 * start. Returns -1 (message set) when there are more than the scratch
 * holds. */
static int prepare_self_contact(implicit_work *w, const rod_model *m, double dt, double margin,
                                rod_report *report)
{
    const int n = w->nodes;
    const double push = 1.0 / (m->ds * (m->mass_per_length / dt + m->options.theta * m->linear_damping));
    for (int i = 0; i < n; i++) w->node_push[i] = push;
    for (int which = 0; which < 2; which++) {
        /* a held end moves with its support (a sleeve's slide is left out
         * of the pairs' compliance: its force still acts) */
        const end_condition *e = &w->ends[which];
        w->node_push[which ? n - 1 : 0] = e->held ? 0.0 : 2.0 * push;
    }
    if (rod_self_contact_find(w->self, w->pos0, margin) < 0) {
        snprintf(report->message, sizeof report->message,
                 "implicit scheme: at t = %.6g s more than %d pairs of segments are within "
                 "%.3g m of each other (self-contact); the rod is packed tighter than a knot: "
                 "use fewer nodes (rod.nodes) or set rod.self_contact = no",
                 w->save_time, w->self->max_pairs, m->diameter + margin);
        return -1;
    }
    return 0;
}

/* The theta-mean tip force and moment over the step, global. */
static void tip_load_mean(const implicit_work *w, const rod_model *m, double t, double dt,
                          const double *frame_th, double tipf[3], double tipm[3])
{
    const double theta = m->options.theta;
    double tipf1[3], tipm1[3];
    tip_load_global(m, t + dt, &frame_th[9 * (w->nodes - 1)], tipf1, tipm1);
    for (int k = 0; k < 3; k++) {
        tipf[k] = theta * tipf1[k] + (1.0 - theta) * w->tipf0[k];
        tipm[k] = theta * tipm1[k] + (1.0 - theta) * w->tipm0[k];
    }
}

static const double zero3[3] = {0.0, 0.0, 0.0};

/* The angular rows of an end node b (0 or NS-1) that has an omega block:
 * (3.6)_2, with each held rotation's row replaced by omega_k = 0 (its
 * unknown is idle). Writes the scaled rows r[0..2]. */
static void end_angular_rows(implicit_work *w, const rod_model *m, const end_condition *e,
                             const double *x, int b, double dt, const double tipm[3],
                             const double *frame_th, double r[3])
{
    double raw[3], om[3];
    const double *xo = block_omega(w, x, b);
    for (int k = 0; k < 3; k++) om[k] = e->clamped ? e->omega1[k] : e->hold_omega[k] ? 0.0 : xo[k];
    if (b == 0) angular_balance(w, m, x, b, dt, tipm, frame_th, om, raw, 0, 1);
    else angular_balance(w, m, x, b, dt, tipm, frame_th, om, raw, 1, 0);
    for (int k = 0; k < 3; k++)
        r[k] = (e->clamped || e->hold_omega[k]) ? xo[k] * dt : raw[k] / w->moment_scale;
}

/* The residual's rows of the blocks b = 1, 2, ... of interior nodes (b <=
 * NS - 2), LANES at a time, as residual's loop writes them one at a time
 * (the same numbers: base/vec3_lanes.h); returns the first block left to
 * it. */
LANES_TARGET static int interior_rows(const implicit_work *w, const rod_model *m, const double *x,
                                      double dt, double *res)
{
    const int n = w->nodes, first = w->first;
    const double theta = m->options.theta, ds = m->ds, dt_ds = dt / ds, inv_dt = 1.0 / dt;
    const double ms = 1.0 / w->moment_scale, wb = ds, arm = 0.5 * ds;
    const double *frame_th = theta < 1.0 ? w->frame_th : w->frame1, *inertia = m->rotary_inertia;
    int b = 1;
    for (; b + LANES <= n - 1; b += LANES) {
        const int j = b - 1;
        lanes vb[3], vj[3], d31j[3], d30j[3], d31b[3], d30b[3], m1b[3], m0b[3], m1j[3], m0j[3];
        lanes nl[3], nr[3], om[3], om0[3], q[9], r[3], total[3], d3[3], cr[3], body[3];
        lanes wbar[3], iw[3], gyro[3];
        lanes_load3(vb, w->vbar, b, 3);
        lanes_load3(vj, w->vbar, j, 3);
        lanes_load3(d31j, w->d3mid1, j, 3);
        lanes_load3(d30j, w->d3mid0, j, 3);
        for (int k = 0; k < 3; k++) r[k] = (vb[k] - vj[k]) * dt_ds - (d31j[k] - d30j[k]);
        lanes_store3(res, b - first, BLOCK, r);
        /* cell_moment with segments on both sides */
        lanes_load3(m1b, w->moment1, b, 3);
        lanes_load3(m0b, w->moment0, b, 3);
        lanes_load3(d31b, w->d3mid1, b, 3);
        lanes_load3(d30b, w->d3mid0, b, 3);
        lanes_load3(nr, x, b + 1 - first, BLOCK); /* block_force */
        for (int k = 0; k < 3; k++) {
            total[k] = theta * m1b[k] + (1.0 - theta) * m0b[k];
            d3[k] = theta * d31b[k] + (1.0 - theta) * d30b[k];
        }
        lanes_cross(cr, d3, nr);
        for (int k = 0; k < 3; k++) total[k] += arm * cr[k];
        lanes_load3(m1j, w->moment1, j, 3);
        lanes_load3(m0j, w->moment0, j, 3);
        lanes_load3(nl, x, b - first, BLOCK);
        for (int k = 0; k < 3; k++) {
            total[k] -= theta * m1j[k] + (1.0 - theta) * m0j[k];
            d3[k] = theta * d31j[k] + (1.0 - theta) * d30j[k];
        }
        lanes_cross(cr, d3, nl);
        for (int k = 0; k < 3; k++) total[k] += arm * cr[k];
        if (w->distributed_moment)
            for (int k = 0; k < 3; k++) total[k] += wb * m->distributed_moment[k];
        if (w->point_moment) {
            lanes point[3];
            lanes_load3(point, w->point_moment, b, 3);
            for (int k = 0; k < 3; k++) total[k] += w->point_factor * point[k];
        }
        /* angular_balance */
        lanes_load9(q, frame_th, b, 9);
        lanes_mul_tv(body, q, total);
        lanes_load3(om, x + 3, b - first, BLOCK); /* block_omega */
        lanes_load3(om0, w->omega0, b, 3);
        for (int k = 0; k < 3; k++) {
            wbar[k] = theta * om[k] + (1.0 - theta) * om0[k];
            iw[k] = inertia[k] * wbar[k];
        }
        lanes_cross(gyro, wbar, iw);
        for (int k = 0; k < 3; k++) {
            const lanes inertial = wb * (inertia[k] * (om[k] - om0[k]) * inv_dt + gyro[k]);
            r[k] = (inertial - body[k] + wb * m->angular_damping * wbar[k]) * ms;
        }
        lanes_store3(res + 3, b - first, BLOCK, r);
    }
    return b;
}

/* Scaled residual of the step t -> t + dt at the iterate x. Interior nodes
 * take the loops without end conditions; the two end nodes follow them. */
static void residual(implicit_work *w, const rod_model *m, const double *x, double t, double dt,
                     double *res)
{
    const int n = w->nodes, first = w->first;
    const double theta = m->options.theta, ds = m->ds, mass = m->mass_per_length;
    /* reciprocals: the loops below multiply (a division per use would cost more
     * than the rest of the line) */
    const double inv_dt = 1.0 / dt, dt_ds = dt / ds;
    end_condition *root = &w->ends[0], *tip = &w->ends[1];

    /* frames at the end of the step and at the theta point; for theta = 1
     * they are the same array */
    const double *frame_th = theta < 1.0 ? w->frame_th : w->frame1;
    if (!w->frames_kept) {
        advance_frames(w, x, 1, n - 1, dt, theta);
        for (int which = 0; which < 2; which++) {
            const end_condition *e = &w->ends[which];
            const int i = which ? n - 1 : 0;
            if (e->clamped) {
                memcpy(&w->frame1[9 * i], e->frame1, 9 * sizeof(double));
                memcpy(&w->frame_th[9 * i], e->frame_th, 9 * sizeof(double));
            } else {
                advance_frame(w, x, i, dt, theta, e->hold_omega);
            }
        }
        end_geometry(m, w->frame1, w->darboux1, w->d3mid1, w->moment1);
    }
    double tipf[3], tipm[3], applied[3];
    tip_load_mean(w, m, t, dt, frame_th, tipf, tipm);

    /* (3.3)_1, linear momentum of the cell of node b (global), solved for the
     * velocity at the end of the step: linear in N, so v is not an unknown */
    const double c = m->linear_damping;
    const int contact = !w->contact_off;
    if (w->want_jacobian) memset(w->touched, 0, (size_t)n);
    const double keep = (mass * inv_dt - (1.0 - theta) * c) / (mass * inv_dt + theta * c);
    const double push = 1.0 / (ds * (mass * inv_dt + theta * c));
    for (int b = 1; b < n - 1; b++) {
        const double *n_left = block_force(w, x, b), *n_right = block_force(w, x, b + 1);
        double *v1 = &w->vel1[3 * b], *vb = &w->vbar[3 * b];
        const double *v0 = &w->vel0[3 * b];
        for (int k = 0; k < 3; k++) {
            double f = n_right[k] - n_left[k] + ds * m->distributed_force[k];
            v1[k] = keep * v0[k] + f * push;
        }
        if (w->point_force)
            v3_axpy(v1, w->point_factor * push, &w->point_force[3 * b]);
        for (int k = 0; k < 3; k++) vb[k] = theta * v1[k] + (1.0 - theta) * v0[k];
        if (contact && w->surface_count) node_contact(w, m, b, push, dt);
    }
    end_velocity(w, m, root, 0, zero3, block_force(w, x, 1), dt, applied);
    end_velocity(w, m, tip, n - 1, block_force(w, x, n - 1), tipf, dt, applied);
    if (contact && w->surface_count)
        for (int which = 0; which < 2; which++)
            if (!w->ends[which].held) node_contact(w, m, which ? n - 1 : 0, 2.0 * push, dt);
    if (contact && w->puncture_count) puncture_forces(w, m, push, dt);
    if (w->self && w->self->count)
        rod_self_contact_forces(w->self, w->pos0, w->vel1, w->vbar, w->node_push, dt, theta,
                                !w->self_off);

    /* (3.14) constraint on segment b-1 and (3.6)_2 on node b: block b */
    const double ms = 1.0 / w->moment_scale;
    for (int b = interior_rows(w, m, x, dt, res); b < n; b++) {
        double *r = &res[BLOCK * (b - first)];
        const int j = b - 1; /* segment to the left of node b */
        for (int k = 0; k < 3; k++)
            r[k] = (w->vbar[3 * b + k] - w->vbar[3 * j + k]) * dt_ds -
                   (w->d3mid1[3 * j + k] - w->d3mid0[3 * j + k]);
        if (b == n - 1) break;
        double raw[3];
        angular_balance(w, m, x, b, dt, tipm, frame_th, block_omega(w, x, b), raw, 1, 1);
        for (int k = 0; k < 3; k++) r[3 + k] = raw[k] * ms;
    }
    end_angular_rows(w, m, tip, x, n - 1, dt, tipm, frame_th, &res[BLOCK * (n - 1 - first) + 3]);
    if (first == 0) {
        /* block 0 has no segment to its left: its first entries are unused */
        for (int k = 0; k < 3; k++) res[k] = x[k] / w->force_scale;
        end_angular_rows(w, m, root, x, 0, dt, tipm, frame_th, &res[3]);
    }
}

/* What the supports exert on the rod over the accepted step (the leftover
 * of the held ends' balances), from the residual's last evaluation at x. */
static void end_reactions(implicit_work *w, const rod_model *m, double t, double dt)
{
    const int n = w->nodes;
    const double theta = m->options.theta, c = m->linear_damping, wb = 0.5 * m->ds;
    const double *frame_th = theta < 1.0 ? w->frame_th : w->frame1;
    double tipf[3], tipm[3];
    tip_load_mean(w, m, t, dt, frame_th, tipf, tipm);
    for (int which = 0; which < 2; which++) {
        end_condition *e = &w->ends[which];
        const int b = which ? n - 1 : 0;
        v3_set(e->reaction, 0.0, 0.0, 0.0);
        v3_set(e->reaction_moment, 0.0, 0.0, 0.0);
        if (!e->held) continue;
        double applied[3];
        const double *n_left = which ? block_force(w, w->x, n - 1) : zero3;
        const double *n_right = which ? tipf : block_force(w, w->x, 1);
        for (int k = 0; k < 3; k++) applied[k] = n_right[k] - n_left[k] + wb * m->distributed_force[k];
        if (w->point_force) v3_axpy(applied, w->point_factor, &w->point_force[3 * b]);
        const double *v1 = &w->vel1[3 * b], *v0 = &w->vel0[3 * b], *vb = &w->vbar[3 * b];
        for (int k = 0; k < 3; k++)
            e->reaction[k] = wb * m->mass_per_length * (v1[k] - v0[k]) / dt + wb * c * vb[k] - applied[k];
        if (!e->clamped && !e->hold_omega[0] && !e->hold_omega[1] && !e->hold_omega[2]) continue;
        double raw[3], om[3];
        for (int k = 0; k < 3; k++)
            om[k] = e->clamped ? e->omega1[k] : e->hold_omega[k] ? 0.0 : block_omega(w, w->x, b)[k];
        if (which) angular_balance(w, m, w->x, b, dt, tipm, frame_th, om, raw, 1, 0);
        else angular_balance(w, m, w->x, b, dt, tipm, frame_th, om, raw, 0, 1);
        for (int k = 0; k < 3; k++)
            if (!e->clamped && !e->hold_omega[k]) raw[k] = 0.0; /* balanced by the motion */
        m3_mul_v(e->reaction_moment, &frame_th[9 * b], raw);
    }
}

/* Planar problem: every load keeps the rod in the x-y plane, so d2 stays
 * along +z, each frame is a rotation about z by phi (d3 = (cos phi, sin phi),
 * d1 = (-sin phi, cos phi)), omega = omega_2 d2 and u = u_2 d2 with
 * u_{i+1/2} = (phi_{i+1} - phi_i) / ds: the same discrete equations as in
 * 3-D, restricted to the plane (the out-of-plane unknowns stay exactly zero),
 * with 5 unknowns per block and no rotation matrices. */

/* Tip force (x, y, N) and moment about z (N m) at time t for a tip angle phi. */
static void tip_load_planar(const rod_model *m, double t, double phi, double force[2],
                            double *moment)
{
    double f[3], mo[3];
    rod_tip_load(m, t, f, mo);
    if (m->tip_frame == ROD_FRAME_DIRECTOR) {
        double c = cos(phi), sn = sin(phi);
        force[0] = -sn * f[0] + c * f[2]; /* f1 d1 + f3 d3 */
        force[1] = c * f[0] + sn * f[2];
        *moment = mo[1];                  /* about d2 = z */
    } else {
        force[0] = f[0];
        force[1] = f[1];
        *moment = mo[2];
    }
}

/* Scaled residual of the planar step; leaves phi1, phi_th, darboux1 (u_2 at
 * 3j+1) and moment1 (z at 3j+2) for the iterate x. */
static void residual_planar(implicit_work *w, const rod_model *m, const double *x, double t,
                            double dt, double *res)
{
    const int n = w->nodes, nb = BLOCK_PLANAR;
    const double theta = m->options.theta, ds = m->ds, mass = m->mass_per_length;
    const double inertia = m->rotary_inertia[1], stiffness = m->stiffness[1];
    w->phi1[0] = w->phi_th[0] = w->phi0[0];
    for (int i = 1; i < n; i++) {
        double wbar = theta * x[nb * (i - 1) + 4] + (1.0 - theta) * w->omega0[3 * i + 1];
        w->phi1[i] = w->phi0[i] + dt * wbar;
        w->phi_th[i] = w->phi0[i] + theta * dt * wbar;
    }
    double *d3x = w->mid1, *d3y = w->mid1 + n; /* scratch: d3 at the midpoints, end of step */
    for (int j = 0; j + 1 < n; j++) {
        double u = (w->phi1[j + 1] - w->phi1[j]) / ds;
        double mid = 0.5 * (w->phi1[j] + w->phi1[j + 1]);
        w->darboux1[3 * j + 1] = u;
        w->moment1[3 * j + 2] = stiffness * u; /* (3.4) M = B u, about z */
        d3x[j] = cos(mid);
        d3y[j] = sin(mid);
    }
    double tipf1[2], tipm1, tipf[2], tipm;
    tip_load_planar(m, t + dt, w->phi_th[n - 1], tipf1, &tipm1);
    for (int k = 0; k < 2; k++) tipf[k] = theta * tipf1[k] + (1.0 - theta) * w->tipf0[k];
    tipm = theta * tipm1 + (1.0 - theta) * w->tipm0[2];

    const double fs = 1.0 / w->force_scale, ms = 1.0 / w->moment_scale;
    for (int b = 1; b < n; b++) {
        double *r = &res[nb * (b - 1)];
        const double *xb = &x[nb * (b - 1)];
        const int j = b - 1;
        const double wb = (b == n - 1) ? 0.5 * ds : ds;
        double vr[2], vl[2] = {0.0, 0.0};
        for (int k = 0; k < 2; k++) {
            vr[k] = theta * xb[2 + k] + (1.0 - theta) * w->vel0[3 * b + k];
            if (b > 1) vl[k] = theta * x[nb * (b - 2) + 2 + k] + (1.0 - theta) * w->vel0[3 * (b - 1) + k];
        }
        /* (3.14) */
        r[0] = (vr[0] - vl[0]) * dt / ds - (d3x[j] - w->d3mid0[3 * j]);
        r[1] = (vr[1] - vl[1]) * dt / ds - (d3y[j] - w->d3mid0[3 * j + 1]);
        /* (3.3)_1 */
        const double *n_left = xb;
        const double *n_right = (b < n - 1) ? xb + nb : tipf;
        for (int k = 0; k < 2; k++) {
            double inertial = wb * mass * (xb[2 + k] - w->vel0[3 * b + k]) / dt;
            double external = wb * (m->distributed_force[k] - m->linear_damping * vr[k]);
            r[2 + k] = (inertial - (n_right[k] - n_left[k]) - external) * fs;
        }
        /* (3.6)_2 about z */
        double m_left = theta * w->moment1[3 * j + 2] + (1.0 - theta) * w->moment0[3 * j + 2];
        double m_right = (b < n - 1)
                             ? theta * w->moment1[3 * b + 2] + (1.0 - theta) * w->moment0[3 * b + 2]
                             : tipm;
        double lx = theta * d3x[j] + (1.0 - theta) * w->d3mid0[3 * j];
        double ly = theta * d3y[j] + (1.0 - theta) * w->d3mid0[3 * j + 1];
        double total = m_right - m_left + 0.5 * ds * (lx * n_left[1] - ly * n_left[0]);
        if (b < n - 1) {
            double rx = theta * d3x[b] + (1.0 - theta) * w->d3mid0[3 * b];
            double ry = theta * d3y[b] + (1.0 - theta) * w->d3mid0[3 * b + 1];
            total += 0.5 * ds * (rx * n_right[1] - ry * n_right[0]);
        }
        double wbar = theta * xb[4] + (1.0 - theta) * w->omega0[3 * b + 1];
        double inertial = wb * inertia * (xb[4] - w->omega0[3 * b + 1]) / dt;
        r[4] = (inertial - total + wb * m->angular_damping * wbar) * ms;
        if (b == 1) {
            /* the clamped root's half cell, at rest: the support holds N_{1/2},
             * M_{1/2} and their arm, and the cell's load */
            end_condition *root = &w->ends[0];
            v3_set(root->reaction, -n_left[0] - 0.5 * ds * m->distributed_force[0],
                   -n_left[1] - 0.5 * ds * m->distributed_force[1], 0.0);
            v3_set(root->reaction_moment, 0.0, 0.0,
                   -m_left - 0.5 * ds * (lx * n_left[1] - ly * n_left[0]));
        }
    }
}

static void evaluate(implicit_work *w, const rod_model *m, const double *x, double t, double dt,
                     double *res)
{
    w->eval_valid = 0; /* the work arrays (velocities, frames, forces) change */
    if (w->planar) residual_planar(w, m, x, t, dt, res);
    else residual(w, m, x, t, dt, res);
    if (x == w->x && res == w->residual && !w->planar && w->want_jacobian && !w->contact_off &&
        !w->self_off && !(w->self && w->self->count)) {
        memcpy(w->eval_x, x, (size_t)w->unknowns * sizeof(double));
        w->eval_t = t;
        w->eval_dt = dt;
        w->eval_valid = 1;
    }
}

/* 1 when residual (and the work arrays, and contact's velocity_jac) hold
 * the whole residual at the iterate x, t, dt: its evaluation can be
 * skipped. A Jacobian renewed in Newton's loop is built at the iterate the
 * loop has just evaluated, and Newton's first residual follows a Jacobian
 * built at the first iterate (suture.ini: 1 evaluation in 7 spared) */
static int evaluated_at_x(const implicit_work *w, double t, double dt)
{
    return w->eval_valid && w->eval_t == t && w->eval_dt == dt &&
           memcmp(w->eval_x, w->x, (size_t)w->unknowns * sizeof(double)) == 0;
}

/* The residual at Newton's iterate x. With contact (its part of the
 * Jacobian in closed form), contact's velocity_jac is recorded too, so that
 * a Jacobian renewed at this iterate need not evaluate it again. */
static void evaluate_iterate(implicit_work *w, const rod_model *m, double t, double dt)
{
    w->want_jacobian = w->contact && !w->contact_fd;
    evaluate(w, m, w->x, t, dt, w->residual);
    w->want_jacobian = 0;
}

/* evaluate_iterate unless the last evaluation already was it (evaluated_at_x) */
static void evaluate_iterate_once(implicit_work *w, const rod_model *m, double t, double dt)
{
    if (!evaluated_at_x(w, t, dt)) evaluate_iterate(w, m, t, dt);
}

static double max_abs(const double *a, int n)
{
    /* branch-free (a data-dependent branch per entry mispredicted often):
     * the maximum over four lanes (independent chains: one lane's latency
     * per entry was 4 % of suture.ini's time), and a sum of a[i] * 0, which
     * is NaN once any entry is NaN or infinite, so that such a residual is
     * never "converged" */
    double m[4] = {0.0, 0.0, 0.0, 0.0}, z[4] = {0.0, 0.0, 0.0, 0.0};
    int i = 0;
    for (; i + 4 <= n; i += 4)
        for (int l = 0; l < 4; l++) {
            const double v = fabs(a[i + l]);
            m[l] = v > m[l] ? v : m[l];
            z[l] += a[i + l] * 0.0;
        }
    for (; i < n; i++) {
        const double v = fabs(a[i]);
        m[0] = v > m[0] ? v : m[0];
        z[0] += a[i] * 0.0;
    }
    const double worst = fmax(fmax(m[0], m[1]), fmax(m[2], m[3]));
    return isnan(z[0] + z[1] + z[2] + z[3]) ? NAN : worst;
}

/* Solves A x = b in place with the factors of band_factor_kl (LAPACK band
 * storage, kl = ku) for count right-hand sides at once (column-major,
 * unknowns apart) whose rows above `first` are 0: the same arithmetic as
 * dgbtrs, written out because the library call's per-column BLAS overhead
 * dominated at this size. Inlined with kl a constant, so that the inner
 * loops have fixed lengths where a column fills the band (unrolled,
 * vectorised); each column's loop runs over its factor's profile only
 * (lower, upper: band_factor_kl), the zeros outside left out. The
 * forward pass starts kl rows above `first` (a row interchange reaches at
 * most kl rows down, so the zeros above stay zero until then); each column
 * of the factors serves every right-hand side while it is in cache (their
 * serial chains interleave); in the back substitution the entry the next
 * column needs, b[j-1], is updated first: it alone is on the serial
 * critical path. */
static inline __attribute__((always_inline)) void band_solve_many_kl(const implicit_work *w,
                                                                    double *restrict b, int count,
                                                                    int first, const int kl)
{
    const int n = w->unknowns, kv = 2 * kl, ld = w->ldab;
    const double *restrict ab = w->band;
    const double *restrict inv_diag = w->inv_diag;
    const lapack_int *restrict pivot = w->pivot;
    const size_t stride = (size_t)n;
    const int *restrict lower = w->lower, *restrict upper = w->upper;
    for (int j = first > kl ? first - kl : 0; j < n - 1; j++) {
        const int p = pivot[j] - 1, len = lower[j];
        const double *col = &ab[(size_t)j * ld + kv + 1];
        for (int c = 0; c < count; c++) {
            double *restrict bc = b + (size_t)c * stride, bj = bc[p];
            bc[p] = bc[j];
            bc[j] = bj;
            /* b[j+1], the next column's entry unless it pivots, updated on
             * its own first, as b[j-1] in the back substitution: out of
             * the vector loop, the next column need not wait for it
             * (0.98x suture.ini's time, the same numbers) */
            if (len == kl) {
                bc[j + 1] -= col[0] * bj;
                for (int i = 1; i < kl; i++) bc[j + 1 + i] -= col[i] * bj;
            } else if (len == SHORT_COLUMN) { /* fixed length: unrolled, vectorised */
                bc[j + 1] -= col[0] * bj;
                for (int i = 1; i < SHORT_COLUMN; i++) bc[j + 1 + i] -= col[i] * bj;
            } else {
                for (int i = 0; i < len; i++) bc[j + 1 + i] -= col[i] * bj;
            }
        }
    }
    for (int j = n - 1; j >= 0; j--) {
        const double *col = &ab[(size_t)j * ld + kv - j]; /* col[i] = U(i, j) */
        const int lo = upper[j];
        for (int c = 0; c < count; c++) {
            double *restrict bc = b + (size_t)c * stride, bj = bc[j] * inv_diag[j];
            bc[j] = bj;
            if (lo < j) {
                bc[j - 1] -= col[j - 1] * bj;
                for (int i = lo; i < j - 1; i++) bc[i] -= col[i] * bj;
            }
        }
    }
}

/* band_solve_many_kl for `lanes` right-hand sides side by side, stored by
 * rows (t[LANES (i * width + v) + l] is row i of right-hand side
 * LANES v + l, width vectors a row): each step of the substitutions updates
 * a whole row of them at once, one vector operation for LANES numbers,
 * where the columns' own loops run 8 or 16 long and wait on the serial
 * chain from one step to the next. The same operations on each right-hand
 * side in the same order as band_solve_many_kl (no fused multiply-add), so
 * the same numbers. */
static inline __attribute__((always_inline)) void
band_solve_rows_kl(const implicit_work *w, lanes *restrict t, int first, const int kl,
                   const int width)
{
    const int n = w->unknowns, kv = 2 * kl, ld = w->ldab;
    const double *restrict ab = w->band;
    const double *restrict inv_diag = w->inv_diag;
    const lapack_int *restrict pivot = w->pivot;
    const int *restrict lower = w->lower, *restrict upper = w->upper;
    for (int j = first > kl ? first - kl : 0; j < n - 1; j++) {
        const int p = pivot[j] - 1, len = lower[j];
        const double *col = &ab[(size_t)j * ld + kv + 1];
        lanes bj[2];
        for (int v = 0; v < width; v++) {
            bj[v] = t[p * width + v];
            t[p * width + v] = t[j * width + v];
            t[j * width + v] = bj[v];
        }
        for (int i = 0; i < len; i++)
            for (int v = 0; v < width; v++) t[(j + 1 + i) * width + v] -= col[i] * bj[v];
    }
    for (int j = n - 1; j >= 0; j--) {
        const double *col = &ab[(size_t)j * ld + kv - j]; /* col[i] = U(i, j) */
        const int lo = upper[j];
        lanes bj[2];
        for (int v = 0; v < width; v++) {
            bj[v] = t[j * width + v] * inv_diag[j];
            t[j * width + v] = bj[v];
        }
        for (int i = lo; i < j; i++)
            for (int v = 0; v < width; v++) t[i * width + v] -= col[i] * bj[v];
    }
}

static inline __attribute__((always_inline)) void
band_solve_rows_width(const implicit_work *w, lanes *t, int first, const int width)
{
    if (w->kl == BAND) band_solve_rows_kl(w, t, first, BAND, width);
    else if (w->kl == BAND_PUNCTURE) band_solve_rows_kl(w, t, first, BAND_PUNCTURE, width);
    else band_solve_rows_kl(w, t, first, BAND_PLANAR, width);
}

/* Solves A x = b (band_solve_many's contract) through band_solve_rows_kl,
 * ROWS_CHUNK right-hand sides at a time (fewer in the last chunk, up to
 * LANES of them in one vector a row), copied into the rows scratch and
 * back. A stand-alone loop at 1446 unknowns (the tight knot's), 45
 * columns: 4.3 us a column against 8.5-11 us one at a time. */
LANES_TARGET static void band_solve_rows(const implicit_work *w, double *b, int count, int first)
{
    const int n = w->unknowns;
    const size_t stride = (size_t)n;
    double *t = w->rows;
    for (int c0 = 0; c0 < count; c0 += ROWS_CHUNK) {
        const int cc = count - c0 < ROWS_CHUNK ? count - c0 : ROWS_CHUNK;
        const int width = cc > LANES ? 2 : 1, wide = LANES * width;
        /* rows above `first` are 0 in every column: the forward pass leaves
         * them so until kl rows above it, where it starts */
        for (int i = 0; i < n; i++) {
            double *ti = t + (size_t)i * (size_t)wide;
            int c = 0;
            for (; c < cc; c++) ti[c] = b[(size_t)(c0 + c) * stride + (size_t)i];
            for (; c < wide; c++) ti[c] = 0.0;
        }
        if (width == 2) band_solve_rows_width(w, (lanes *)t, first, 2);
        else band_solve_rows_width(w, (lanes *)t, first, 1);
        for (int c = 0; c < cc; c++) {
            double *bc = b + (size_t)(c0 + c) * stride;
            for (int i = 0; i < n; i++) bc[i] = t[(size_t)i * (size_t)wide + (size_t)c];
        }
    }
}

static void band_solve_many(const void *ctx, double *b, int count, int first)
{
    const implicit_work *w = ctx;
    if (w->rows && count > 1) band_solve_rows(w, b, count, first);
    else if (w->kl == BAND) band_solve_many_kl(w, b, count, first, BAND);
    else if (w->kl == BAND_PUNCTURE) band_solve_many_kl(w, b, count, first, BAND_PUNCTURE);
    else band_solve_many_kl(w, b, count, first, BAND_PLANAR);
}

static void band_solve(const implicit_work *w, double *b)
{
    if (w->kl == BAND) band_solve_many_kl(w, b, 1, 0, BAND);
    else if (w->kl == BAND_PUNCTURE) band_solve_many_kl(w, b, 1, 0, BAND_PUNCTURE);
    else band_solve_many_kl(w, b, 1, 0, BAND_PLANAR);
}

/* Finite-difference Jacobian into band by a (2 reach + 1)-colouring of the
 * blocks (3 colours: 18 residual evaluations, 15 in the plane), where a
 * block's unknowns reach the rows of `reach` blocks each side. */
static void fd_jacobian(implicit_work *w, const rod_model *m, double t, double dt, int reach)
{
    const int nu = w->unknowns, kl = w->kl, ku = w->kl, ld = w->ldab, nb = w->block;
    w->trail_valid = 0; /* band no longer holds factors */
    memset(w->band, 0, (size_t)ld * (size_t)nu * sizeof(double));
    /* the self-contact forces are unknowns of their own: they act on the
     * residual as constants here, so the band is d r / d x without them
     * (they join in newton_solve) */
    w->self_off = 1;
    evaluate(w, m, w->x, t, dt, w->residual);
    const int colors = 2 * reach + 1;
    /* the force components first, every colour: in 3-D the frames depend on
     * omega alone, so these evaluations keep the ones just computed at x
     * (frames_kept: the exponentials and logarithms, about half of an
     * evaluation, skipped; the same numbers to the last bit) */
    for (int comp = 0; comp < nb; comp++) {
        w->frames_kept = !w->planar && w->var_kind[comp] == 0;
        for (int color = 0; color < colors; color++) {
            double *xp = w->dx; /* scratch copy of x */
            memcpy(xp, w->x, (size_t)nu * sizeof(double));
            for (int b = w->first + color; b < w->nodes; b += colors) {
                int col = nb * (b - w->first) + comp;
                double h = w->fd_step * fmax(fabs(xp[col]), w->var_scale[w->var_kind[comp]]);
                xp[col] += h;
            }
            evaluate(w, m, xp, t, dt, w->perturbed);
            for (int b = w->first + color; b < w->nodes; b += colors) {
                int col = nb * (b - w->first) + comp;
                double h = xp[col] - w->x[col];
                /* blocks b-reach..b+reach */
                int row_lo = nb * (b - w->first - reach), row_hi = nb * (b - w->first + reach + 1);
                if (row_lo < 0) row_lo = 0;
                if (row_hi > nu) row_hi = nu;
                if (row_lo < col - ku) row_lo = col - ku;
                if (row_hi > col + kl + 1) row_hi = col + kl + 1;
                for (int row = row_lo; row < row_hi; row++) {
                    double d = (w->perturbed[row] - w->residual[row]) / h;
                    w->band[(size_t)(kl + ku + row - col) + (size_t)col * (size_t)ld] = d;
                }
            }
        }
    }
    w->frames_kept = 0;
    w->self_off = 0;
}

/* ---- The rod's Jacobian in closed form (issue 11's speed, issue 12's
 * convergence). The same d r / d x as fd_jacobian with contact, punctures
 * and the pairs' laws left out (contact_off, self_off), in 3-D; built from
 * one residual evaluation (the frames at x) and per-node and per-segment
 * 3 x 3 algebra, instead of 18 evaluations, and exact (the differences'
 * step of 1e-7 left errors near 1e-7 relative, so Newton converged linearly
 * where it could converge quadratically). test_jacobian compares the two on
 * every kind of end, both thetas and follower loads.
 *
 * Rotations are perturbed on the right (in the body frame):
 *   exp(a + d) = exp(a) exp(J(a) d),  log(R exp(e)) = log(R) + J(log R)^-1 e,
 *   J(a) = I - (1 - cos x)/x^2 [a]x + (x - sin x)/x^3 [a]x^2,   x = |a|,
 *   J(a)^-1 = I + [a]x / 2 + (1/x^2 - (1 + cos x)/(2 x sin x)) [a]x^2
 * (the right Jacobian of SO(3) and its inverse). A change d omega_i of a
 * node's angular velocity turns its end frame by e_i = dt theta J(a_i)
 * d omega_i, a_i = dt omega_bar_i; the segment's phi = log(Q_j^T Q_{j+1})
 * by J(phi)^-1 (e_{j+1} - R^T e_j), R = Q_j^T Q_{j+1}; and d3 and M of the
 * segment, Q_j exp(phi/2) e3 and Q_j exp(phi/2) B (phi/ds - u0), by the
 * chain rule through both. */

/* r = [a]x (row-major) */
static void skew3(double r[9], const double a[3])
{
    r[0] = 0.0;   r[1] = -a[2]; r[2] = a[1];
    r[3] = a[2];  r[4] = 0.0;   r[5] = -a[0];
    r[6] = -a[1]; r[7] = a[0];  r[8] = 0.0;
}

/* r = I + c1 [a]x + c2 [a]x^2 */
static void so3_series(double r[9], const double a[3], double c1, double c2)
{
    const double t = v3_dot(a, a);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r[3 * i + j] = (i == j) * (1.0 - c2 * t) + c2 * a[i] * a[j];
    r[1] -= c1 * a[2]; r[2] += c1 * a[1];
    r[3] += c1 * a[2]; r[5] -= c1 * a[0];
    r[6] -= c1 * a[1]; r[7] += c1 * a[0];
}

/* The right Jacobian J(a) of exp on SO(3) */
static void so3_jacobian(double r[9], const double a[3])
{
    const double t = v3_dot(a, a);
    double s, b; /* sin(x)/x, (1 - cos x)/x^2 */
    m3_exp_coefficients(t, &s, &b);
    /* (x - sin x)/x^3 = (1 - s)/x^2: a series below x = 0.05 (no cancellation) */
    double c2 = t < 2.5e-3 ? (1.0 / 6.0) * (1.0 - t * (1.0 / 20.0) * (1.0 - t * (1.0 / 42.0) *
                                                                    (1.0 - t * (1.0 / 72.0))))
                           : (1.0 - s) / t;
    so3_series(r, a, -b, c2);
}

/* Its inverse J(a)^-1 (|a| < pi) */
static void so3_jacobian_inverse(double r[9], const double a[3])
{
    const double t = v3_dot(a, a);
    double c2;
    if (t < 2.5e-3) {
        c2 = 1.0 / 12.0 + t * (1.0 / 720.0 + t * (1.0 / 30240.0 + t * (1.0 / 1209600.0)));
    } else {
        double s, b;
        m3_exp_coefficients(t, &s, &b);
        c2 = (1.0 - 0.5 * s / b) / t; /* x sin x / (2 (1 - cos x)) = s / 2b */
    }
    so3_series(r, a, 0.5, c2);
}

/* r = a b^T (b transposed) */
static void m3_mul_nt(double r[9], const double a[9], const double b[9])
{
    double p[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            p[3 * i + j] = a[3 * i] * b[3 * j] + a[3 * i + 1] * b[3 * j + 1] + a[3 * i + 2] * b[3 * j + 2];
    for (int k = 0; k < 9; k++) r[k] = p[k];
}

/* band(row block, col block) += s M, 3 x 3 at offsets (ro, co) within the blocks */
static void band_add3(implicit_work *w, int rb, int ro, int cb, int co, const double mtx[9],
                      double s)
{
    if (rb < w->first || cb < w->first || rb >= w->nodes || cb >= w->nodes) return;
    const int kl = w->kl, ld = w->ldab;
    const int row0 = BLOCK * (rb - w->first) + ro, col0 = BLOCK * (cb - w->first) + co;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            const int row = row0 + i, col = col0 + j;
            if (row - col > kl || col - row > kl) continue; /* zero by the band's analysis */
            w->band[(size_t)(2 * kl + row - col) + (size_t)col * (size_t)ld] += s * mtx[3 * i + j];
        }
}

/* The omega components an end node holds (NULL inside) and whether its
 * frame is fixed over the step (clamped, or no omega unknown). */
static const int *node_hold(const implicit_work *w, int i, int *fixed)
{
    const end_condition *e = i == 0 ? &w->ends[0] : i == w->nodes - 1 ? &w->ends[1] : NULL;
    *fixed = (e && e->clamped) || i < w->first;
    return e ? e->hold_omega : NULL;
}

/* d vbar_i / d N_{c-1/2} for the force block c (i or i + 1), 3 x 3; 0 when
 * none. Interior nodes: (3.3)_1; ends: end_velocity's (free: twice the
 * compliance; held: the path's; sliding: projected on the slide). */
static int vbar_force_slope(const implicit_work *w, const rod_model *m, int i, int c, double push,
                            double r[9])
{
    const double theta = m->options.theta;
    const int n = w->nodes;
    double g;
    const end_condition *e = i == 0 ? &w->ends[0] : i == n - 1 ? &w->ends[1] : NULL;
    if (c == i + 1) g = theta * push; /* N_{i+1/2} pulls node i forward */
    else g = -theta * push;
    if (e) {
        if (e->held && !e->sliding) return 0;
        if ((i == 0 && c != 1) || (i == n - 1 && c != n - 1)) return 0;
        g *= 2.0;
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                r[3 * a + b] = e->sliding ? g * e->slide[a] * e->slide[b] : g * (a == b);
        return 1;
    }
    if (c != i && c != i + 1) return 0;
    for (int k = 0; k < 9; k++) r[k] = g * (k % 4 == 0);
    return 1;
}

/* Segment j's part of analytic_jacobian: d d3 / d omega_j, d omega_{j+1}
 * and d M / the same, into jac_seg, from the node's turn matrices E */
static inline __attribute__((always_inline)) void
jacobian_segment(implicit_work *w, const rod_model *m, const double *turn, int j)
{
    const double ds = m->ds;
    double *seg = w->jac_seg;
    double *d3l = &seg[36 * j], *d3r = d3l + 9, *dml = d3l + 18, *dmr = d3l + 27;
    const double *q = &w->frame1[9 * j];
    double phi[3], h[3], rel[9], eh[9], jh[9], jinv[9], bu[3], ehe3[3], ehbu[3];
    for (int k = 0; k < 3; k++) {
        phi[k] = ds * w->darboux1[3 * j + k];
        h[k] = 0.5 * phi[k];
        bu[k] = m->stiffness[k] * (w->darboux1[3 * j + k] - m->intrinsic_curvature[k]);
    }
    m3_mul_tn(rel, q, &w->frame1[9 * (j + 1)]);
    m3_exp(eh, h);
    so3_jacobian(jh, h);
    so3_jacobian_inverse(jinv, phi);
    m3_column(ehe3, eh, 2);
    m3_mul_v(ehbu, eh, bu);
    double qeh[9], s3[9], sbu[9], p3[9], pm[9], tmp[9], a3r[9], a3l[9], amr[9], aml[9];
    m3_mul(qeh, q, eh);
    /* P3 = -Q exp(h) [e3]x J(h) / 2 */
    const double e3[3] = {0.0, 0.0, 1.0};
    skew3(s3, e3);
    m3_mul(tmp, s3, jh);
    m3_mul(p3, qeh, tmp);
    for (int k = 0; k < 9; k++) p3[k] *= -0.5;
    /* PM = Q exp(h) (B / ds - [bu]x J(h) / 2) */
    skew3(sbu, bu);
    m3_mul(tmp, sbu, jh);
    for (int k = 0; k < 9; k++) tmp[k] *= -0.5;
    for (int k = 0; k < 3; k++) tmp[4 * k] += m->stiffness[k] / ds;
    m3_mul(pm, qeh, tmp);
    /* right: P J^-1; left: -Q [exp(h) v]x - P J^-1 R^T */
    m3_mul(a3r, p3, jinv);
    m3_mul(amr, pm, jinv);
    m3_mul_nt(tmp, a3r, rel);
    double qs[9], sv[9];
    skew3(sv, ehe3);
    m3_mul(qs, q, sv);
    for (int k = 0; k < 9; k++) a3l[k] = -qs[k] - tmp[k];
    m3_mul_nt(tmp, amr, rel);
    skew3(sv, ehbu);
    m3_mul(qs, q, sv);
    for (int k = 0; k < 9; k++) aml[k] = -qs[k] - tmp[k];
    m3_mul(d3l, a3l, &turn[18 * j]);
    m3_mul(d3r, a3r, &turn[18 * (j + 1)]);
    m3_mul(dml, aml, &turn[18 * j]);
    m3_mul(dmr, amr, &turn[18 * (j + 1)]);
}

/* skew3 of lanes */
static inline __attribute__((always_inline)) void lanes_skew(lanes r[9], const lanes a[3])
{
    const lanes zero = {0.0};
    r[0] = zero; r[1] = -a[2]; r[2] = a[1];
    r[3] = a[2]; r[4] = zero;  r[5] = -a[0];
    r[6] = -a[1]; r[7] = a[0]; r[8] = zero;
}

/* so3_series of lanes (t = |a|^2 given) */
static inline __attribute__((always_inline)) void
lanes_so3_series(lanes r[9], const lanes a[3], const lanes *t, const lanes *c1_of, const lanes *c2_of)
{
    const lanes c1 = *c1_of, c2 = *c2_of;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r[3 * i + j] = (double)(i == j) * (1.0 - c2 * *t) + c2 * a[i] * a[j];
    r[1] -= c1 * a[2]; r[2] += c1 * a[1];
    r[3] += c1 * a[2]; r[5] -= c1 * a[0];
    r[6] -= c1 * a[1]; r[7] += c1 * a[0];
}

/* where[l] ? a[l] : b[l] */
static inline __attribute__((always_inline)) void
lanes_select(lanes *r, const lanes_mask *where, const lanes *a, const lanes *b)
{
    const lanes_mask ai = (lanes_mask)*a, bi = (lanes_mask)*b;
    *r = (lanes)((*where & ai) | (~*where & bi));
}

/* jacobian_segment for every segment, LANES at a time (the same numbers:
 * base/vec3_lanes.h; one at a time where a segment turns too far for the
 * series and at the end) */
LANES_TARGET static void jacobian_segments(implicit_work *w, const rod_model *m, const double *turn)
{
    const int segments = w->nodes - 1;
    const double ds = m->ds;
    int j = 0;
    for (; j + LANES <= segments; j += LANES) {
        lanes phi[3], h[3], bu[3], dar[3], th, tp;
        lanes_load3(dar, w->darboux1, j, 3);
        for (int k = 0; k < 3; k++) {
            phi[k] = ds * dar[k];
            h[k] = 0.5 * phi[k];
            bu[k] = m->stiffness[k] * (dar[k] - m->intrinsic_curvature[k]);
        }
        /* so3_jacobian_inverse(phi) takes m3_exp_coefficients' series above
         * t = 2.5e-3 only within it; exp(h) and J(h) always */
        if (!lanes_exp_in_series(phi, &tp) || !lanes_exp_in_series(h, &th)) {
            for (int l = 0; l < LANES; l++) jacobian_segment(w, m, turn, j + l);
            continue;
        }
        lanes q[9], next[9], rel[9], eh[9], jh[9], jinv[9], ehe3[3], ehbu[3];
        lanes_load9(q, w->frame1, j, 9);
        lanes_load9(next, w->frame1, j + 1, 9);
        lanes_mul_tn(rel, q, next);
        lanes_exp(eh, h, &th);
        {   /* so3_jacobian(jh, h) */
            lanes s, b;
            lanes_exp_coefficients(&th, &s, &b);
            const lanes series = (1.0 / 6.0) * (1.0 - th * (1.0 / 20.0) * (1.0 - th * (1.0 / 42.0) *
                                                                          (1.0 - th * (1.0 / 72.0))));
            const lanes_mask small = th < 2.5e-3;
            const lanes other = (1.0 - s) / th, minus_b = -b;
            lanes c2;
            lanes_select(&c2, &small, &series, &other);
            lanes_so3_series(jh, h, &th, &minus_b, &c2);
        }
        {   /* so3_jacobian_inverse(jinv, phi) */
            lanes s, b;
            lanes_exp_coefficients(&tp, &s, &b);
            const lanes series = 1.0 / 12.0 + tp * (1.0 / 720.0 + tp * (1.0 / 30240.0 + tp * (1.0 / 1209600.0)));
            const lanes_mask small = tp < 2.5e-3;
            const lanes other = (1.0 - 0.5 * s / b) / tp, half = {0.5, 0.5, 0.5, 0.5};
            lanes c2;
            lanes_select(&c2, &small, &series, &other);
            lanes_so3_series(jinv, phi, &tp, &half, &c2);
        }
        for (int k = 0; k < 3; k++) ehe3[k] = eh[3 * k + 2]; /* m3_column(eh, 2) */
        lanes_mul_v(ehbu, eh, bu);
        lanes qeh[9], s3[9], sbu[9], p3[9], pm[9], tmp[9], a3r[9], a3l[9], amr[9], aml[9];
        lanes_mul(qeh, q, eh);
        const lanes zero = {0.0}, one = zero + 1.0;
        const lanes e3[3] = {zero, zero, one};
        lanes_skew(s3, e3);
        lanes_mul(tmp, s3, jh);
        lanes_mul(p3, qeh, tmp);
        for (int k = 0; k < 9; k++) p3[k] *= -0.5;
        lanes_skew(sbu, bu);
        lanes_mul(tmp, sbu, jh);
        for (int k = 0; k < 9; k++) tmp[k] *= -0.5;
        for (int k = 0; k < 3; k++) tmp[4 * k] += m->stiffness[k] / ds;
        lanes_mul(pm, qeh, tmp);
        lanes_mul(a3r, p3, jinv);
        lanes_mul(amr, pm, jinv);
        lanes_mul_nt(tmp, a3r, rel);
        lanes qs[9], sv[9];
        lanes_skew(sv, ehe3);
        lanes_mul(qs, q, sv);
        for (int k = 0; k < 9; k++) a3l[k] = -qs[k] - tmp[k];
        lanes_mul_nt(tmp, amr, rel);
        lanes_skew(sv, ehbu);
        lanes_mul(qs, q, sv);
        for (int k = 0; k < 9; k++) aml[k] = -qs[k] - tmp[k];
        lanes el[9], er[9], out[9];
        lanes_load9(el, turn, j, 18);
        lanes_load9(er, turn, j + 1, 18);
        lanes_mul(out, a3l, el);
        lanes_store9(w->jac_seg, j, 36, out);
        lanes_mul(out, a3r, er);
        lanes_store9(w->jac_seg + 9, j, 36, out);
        lanes_mul(out, aml, el);
        lanes_store9(w->jac_seg + 18, j, 36, out);
        lanes_mul(out, amr, er);
        lanes_store9(w->jac_seg + 27, j, 36, out);
    }
    for (; j < segments; j++) jacobian_segment(w, m, turn, j);
}

static void analytic_jacobian(implicit_work *w, const rod_model *m, double t, double dt)
{
    const int n = w->nodes, first = w->first;
    const double theta = m->options.theta, ds = m->ds, c = m->linear_damping;
    const double inv_ms = 1.0 / w->moment_scale, dt_ds = dt / ds;
    const double push = 1.0 / (ds * (m->mass_per_length / dt + theta * c));
    const double *frame_th = theta < 1.0 ? w->frame_th : w->frame1;
    w->trail_valid = 0; /* band no longer holds factors */
    memset(w->band, 0, (size_t)w->ldab * (size_t)w->unknowns * sizeof(double));
    /* frames and moments at x: all the rod's part reads of the evaluation.
     * Without self-contact pairs and with contact on, the
     * evaluation is the iterate's own, contact's velocity maps included,
     * which add_contact_jacobian and Newton's first residual then reuse
     * (evaluated_at_x): one evaluation per Jacobian instead of two */
    if (w->contact_off || (w->self && w->self->count)) {
        w->self_off = 1; /* the pairs' forces as constants (fd_jacobian) */
        evaluate(w, m, w->x, t, dt, w->residual);
        w->self_off = 0;
    } else {
        evaluate_iterate(w, m, t, dt);
    }
    double *turn = w->jac_node; /* per node: E (d e / d omega), Eth (at the theta point) */
    for (int i = 0; i < n; i++) {
        double *e1 = &turn[18 * i], *eth = e1 + 9;
        int fixed;
        const int *hold = node_hold(w, i, &fixed);
        if (fixed) {
            memset(e1, 0, 18 * sizeof(double));
            continue;
        }
        const double *om = block_omega(w, w->x, i);
        double a[3];
        for (int k = 0; k < 3; k++) {
            a[k] = dt * (theta * om[k] + (1.0 - theta) * w->omega0[3 * i + k]);
            if (hold && hold[k]) a[k] = 0.0;
        }
        so3_jacobian(e1, a);
        for (int k = 0; k < 9; k++) e1[k] *= dt * theta;
        if (theta < 1.0) {
            v3_scale(a, a, theta);
            so3_jacobian(eth, a);
            for (int k = 0; k < 9; k++) eth[k] *= theta * dt * theta;
        } else {
            memcpy(eth, e1, 9 * sizeof(double));
        }
        if (hold)
            for (int k = 0; k < 3; k++)
                if (hold[k])
                    for (int r = 0; r < 3; r++) e1[3 * r + k] = eth[3 * r + k] = 0.0;
    }
    /* per segment: d d3 / d omega_j, d omega_{j+1} and d M / the same */
    double *seg = w->jac_seg;
    jacobian_segments(w, m, turn);
    /* a follower tip load turns with the tip's frame at the theta point */
    double dtipf[9] = {0}, dtipm[9] = {0};
    if (m->tip_frame == ROD_FRAME_DIRECTOR) {
        double f[3], mo[3], sk[9];
        const double *qt = &frame_th[9 * (n - 1)], *eth = &turn[18 * (n - 1) + 9];
        rod_tip_load(m, t + dt, f, mo);
        skew3(sk, f);
        m3_mul(dtipf, qt, sk);
        m3_mul(dtipf, dtipf, eth);
        skew3(sk, mo);
        m3_mul(dtipm, qt, sk);
        m3_mul(dtipm, dtipm, eth);
        for (int k = 0; k < 9; k++) {
            dtipf[k] *= -theta;
            dtipm[k] *= -theta;
        }
    }
    /* (3.14) rows of block b (segment j = b - 1):
     * (vbar_b - vbar_j) dt/ds - (d3_j(t+dt) - d3_j(t)) */
    for (int b = 1; b < n; b++) {
        const int j = b - 1;
        double g[9];
        for (int cb = j; cb <= b + 1; cb++) {
            if (cb < 1 || cb > n - 1) continue;
            if (vbar_force_slope(w, m, b, cb, push, g)) band_add3(w, b, 0, cb, 0, g, dt_ds);
            if (vbar_force_slope(w, m, j, cb, push, g)) band_add3(w, b, 0, cb, 0, g, -dt_ds);
        }
        if (b == n - 1 && !(w->ends[1].held && !w->ends[1].sliding) &&
            m->tip_frame == ROD_FRAME_DIRECTOR) {
            /* the tip's velocity carries the follower force */
            const end_condition *e = &w->ends[1];
            double p[9];
            for (int k = 0; k < 9; k++) p[k] = dtipf[k];
            if (e->sliding) {
                double ss[9];
                for (int a = 0; a < 3; a++)
                    for (int bb = 0; bb < 3; bb++) ss[3 * a + bb] = e->slide[a] * e->slide[bb];
                m3_mul(p, ss, p);
            }
            band_add3(w, b, 0, b, 3, p, 2.0 * theta * push * dt_ds);
        }
        band_add3(w, b, 0, j, 3, &seg[36 * j], -1.0);
        band_add3(w, b, 0, b, 3, &seg[36 * j + 9], -1.0);
    }
    /* (3.6)_2 rows of each node with an omega block */
    for (int b = first; b < n; b++) {
        const end_condition *e = b == 0 ? &w->ends[0] : b == n - 1 ? &w->ends[1] : NULL;
        const int left = b > 0, right = b < n - 1;
        const double wb = (left && right) ? ds : 0.5 * ds;
        int fixed;
        const int *hold = node_hold(w, b, &fixed);
        int replaced[3] = {0, 0, 0};
        if (e)
            for (int k = 0; k < 3; k++) replaced[k] = e->clamped || e->hold_omega[k];
        /* the moment the balance is written for, in the body frame */
        double total[3], d3r[3] = {0}, d3l[3] = {0}, tipf[3], tipm[3] = {0};
        if (!right) tip_load_mean(w, m, t, dt, frame_th, tipf, tipm);
        cell_moment(w, m, w->x, b, tipm, left, right, total, d3l, d3r);
        const double *qth = &frame_th[9 * b];
        double body[3], qtt[9], own[9], sk[9], tmp[9], blk[9];
        m3_mul_tv(body, qth, total);
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < 3; k++) qtt[3 * i + k] = qth[3 * k + i]; /* Q_th^T */
        /* own omega: inertia, gyroscopic and damping terms, and the turn of
         * the frame the balance is written in: -[body]x Eth */
        const double *om = block_omega(w, w->x, b), *inertia = m->rotary_inertia;
        double wbar[3], iw[3];
        for (int k = 0; k < 3; k++) {
            double o = (hold && hold[k]) || fixed ? 0.0 : om[k];
            wbar[k] = theta * o + (1.0 - theta) * w->omega0[3 * b + k];
            iw[k] = inertia[k] * wbar[k];
        }
        skew3(sk, wbar);
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < 3; k++) own[3 * i + k] = wb * theta * sk[3 * i + k] * inertia[k];
        skew3(sk, iw);
        for (int k = 0; k < 9; k++) own[k] -= wb * theta * sk[k];
        for (int k = 0; k < 3; k++)
            own[4 * k] += wb * (inertia[k] / dt + m->angular_damping * theta);
        if (hold)
            for (int k = 0; k < 3; k++)
                if (hold[k])
                    for (int r = 0; r < 3; r++) own[3 * r + k] = 0.0;
        skew3(sk, body);
        m3_mul(tmp, sk, &turn[18 * b + 9]);
        for (int k = 0; k < 9; k++) own[k] -= tmp[k];
        /* -Q_th^T d total: the columns it reaches, accumulated before the
         * rows a held rotation replaces are dropped */
        double dom[3][9], dn[2][9]; /* omega_{b-1}, omega_b, omega_{b+1}; N_b, N_{b+1} */
        memset(dom, 0, sizeof dom);
        memset(dn, 0, sizeof dn);
        if (right) {
            const double *s = &seg[36 * b], *nr = block_force(w, w->x, b + 1);
            double snr[9];
            skew3(snr, nr);
            for (int k = 0; k < 9; k++) {
                dom[1][k] += theta * s[18 + k];
                dom[2][k] += theta * s[27 + k];
            }
            m3_mul(tmp, snr, s);     /* [N]x d3l */
            for (int k = 0; k < 9; k++) dom[1][k] -= 0.5 * ds * theta * tmp[k];
            m3_mul(tmp, snr, s + 9);
            for (int k = 0; k < 9; k++) dom[2][k] -= 0.5 * ds * theta * tmp[k];
            skew3(dn[1], d3r);
            for (int k = 0; k < 9; k++) dn[1][k] *= 0.5 * ds;
        } else {
            for (int k = 0; k < 9; k++) dom[1][k] += dtipm[k];
        }
        if (left) {
            const double *s = &seg[36 * (b - 1)], *nl = block_force(w, w->x, b);
            double snl[9];
            skew3(snl, nl);
            for (int k = 0; k < 9; k++) {
                dom[0][k] -= theta * s[18 + k];
                dom[1][k] -= theta * s[27 + k];
            }
            m3_mul(tmp, snl, s);
            for (int k = 0; k < 9; k++) dom[0][k] -= 0.5 * ds * theta * tmp[k];
            m3_mul(tmp, snl, s + 9);
            for (int k = 0; k < 9; k++) dom[1][k] -= 0.5 * ds * theta * tmp[k];
            skew3(dn[0], d3l);
            for (int k = 0; k < 9; k++) dn[0][k] *= 0.5 * ds;
        }
        for (int o = 0; o < 3; o++) {
            m3_mul(blk, qtt, dom[o]);
            for (int k = 0; k < 9; k++) blk[k] = -blk[k];
            if (o == 1) for (int k = 0; k < 9; k++) blk[k] += own[k];
            for (int r = 0; r < 3; r++)
                if (replaced[r]) for (int k = 0; k < 3; k++) blk[3 * r + k] = 0.0;
            band_add3(w, b, 3, b - 1 + o, 3, blk, inv_ms);
        }
        for (int o = 0; o < 2; o++) {
            if (b + o < 1 || b + o > n - 1) continue;
            m3_mul(blk, qtt, dn[o]);
            for (int k = 0; k < 9; k++) blk[k] = -blk[k];
            for (int r = 0; r < 3; r++)
                if (replaced[r]) for (int k = 0; k < 3; k++) blk[3 * r + k] = 0.0;
            band_add3(w, b, 3, b + o, 0, blk, inv_ms);
        }
        for (int r = 0; r < 3; r++)
            if (replaced[r]) {
                double one[9] = {0};
                one[4 * r] = dt;
                band_add3(w, b, 3, b, 3, one, 1.0);
            }
    }
    if (first == 0) {
        /* block 0's unused entries: x / force_scale */
        double one[9] = {0};
        for (int k = 0; k < 3; k++) one[4 * k] = 1.0 / w->force_scale;
        band_add3(w, 0, 0, 0, 0, one, 1.0);
    }
}

/* The contact's part of the Jacobian at the iterate x, added onto band.
 * Only the (3.14) rows see contact, through the end-of-step velocities:
 * r_b = theta dt/ds (v_b - v_{b-1}) + ..., v = V(u) the velocities after
 * contact and punctures, u the free ones of (3.3)_1, d u_b / d N_{b-1/2} =
 * -p_b I and d u_b / d N_{b+1/2} = p_b I with p_b the node's compliance
 * (push; twice at a free end; 0 at a held end, whose velocity is its
 * support's). The finite differences of the residual without contact give
 * the Jacobian for V(u) = u, so this adds theta dt/ds E (dV/du - I) du/dN,
 * dV/du recorded in closed form by node_contact and puncture_forces (no
 * finite difference resolves friction's turn within its creep speed well).
 * Left out: a follower tip load's turn with the tip's omega at a free tip
 * in contact, and a sliding end's motion under a puncture beside it. */
static void add_contact_jacobian(implicit_work *w, const rod_model *m, double t, double dt,
                                 int col_from)
{
    evaluate_iterate_once(w, m, t, dt);
    const int n = w->nodes, kl = w->kl, ld = w->ldab, first = w->first;
    const double theta = m->options.theta, c = m->linear_damping;
    const double push = 1.0 / (m->ds * (m->mass_per_length / dt + theta * c));
    const double coef = theta * dt / m->ds;
    for (int b = 0; b < n; b++) {
        if (!w->touched[b]) continue;
        for (int o = -1; o <= 1; o++) {
            const int bp = b + o; /* the node whose free velocity moves v_b */
            if (bp < 0 || bp >= n) continue;
            const int end = bp == 0 ? 0 : bp == n - 1 ? 1 : -1;
            const double p = end < 0 ? push : w->ends[end].held ? 0.0 : 2.0 * push;
            if (p == 0.0) continue;
            double delta[9];
            memcpy(delta, &w->velocity_jac[27 * b + 9 * (o + 1)], sizeof delta);
            if (o == 0)
                for (int k = 0; k < 3; k++) delta[4 * k] -= 1.0;
            for (int side = 0; side < 2; side++) {
                const int cb = bp + side; /* force block: N_{bp-1/2} (left) or N_{bp+1/2} */
                if (cb < 1 || cb > n - 1) continue;
                for (int rs = 0; rs < 2; rs++) {
                    const int rb = b + rs; /* v_b enters r_b (+) and r_{b+1} (-) */
                    if (rb < 1 || rb > n - 1) continue;
                    const double g = coef * p * (side ? 1.0 : -1.0) * (rs ? -1.0 : 1.0);
                    for (int k = 0; k < 3; k++)
                        for (int l = 0; l < 3; l++) {
                            const int row = BLOCK * (rb - first) + k, col = BLOCK * (cb - first) + l;
                            if (row - col > kl || col - row > kl) continue; /* not in the band */
                            if (col < col_from) continue; /* factored already */
                            w->band[(size_t)(2 * kl + row - col) + (size_t)col * (size_t)ld] +=
                                g * delta[3 * k + l];
                        }
                }
            }
        }
    }
}

/* Step j's rank-1 update of columns j+c0 .. j+c1 (c0 >= 1) with L's
 * column j (col, its len entries below the diagonal; the diagonal entry at
 * col[0]), upper[] noting the first row of U that is not zero. The short
 * case from a copy of L's column: the columns it updates lie in the same
 * array, and the compiler, unable to rule out that they overlap it, left
 * the loop scalar (the same operations in the same order either way; 0.92x
 * suture.ini's time). */
static inline __attribute__((always_inline)) void
band_update(double *restrict col, int j, int c0, int c1, int len, int ld, int *restrict upper)
{
    if (len == SHORT_COLUMN) {
        double l[SHORT_COLUMN];
        for (int i = 0; i < SHORT_COLUMN; i++) l[i] = col[i + 1];
        for (int c = c0; c <= c1; c++) {
            double *a = &col[(size_t)c * (size_t)(ld - 1) + 1];
            const double u = a[-1]; /* U(j, j + c), final */
            if (u != 0.0) {
                if (upper[j + c] > j) upper[j + c] = j;
                for (int i = 0; i < SHORT_COLUMN; i++) a[i] -= l[i] * u;
            }
        }
    } else {
        for (int c = c0; c <= c1; c++) {
            double *a = &col[(size_t)c * (size_t)(ld - 1)];
            const double u = a[0];
            if (u != 0.0) {
                if (upper[j + c] > j) upper[j + c] = j;
                for (int i = 1; i <= len; i++) a[i] -= col[i] * u;
            }
        }
    }
}

/* Rows j and j + jp interchanged over columns j+c0 .. j+c1 (stride ld - 1
 * along a row) */
static inline __attribute__((always_inline)) void
band_swap(double *col, int jp, int c0, int c1, int ld)
{
    for (int c = c0; c <= c1; c++) {
        double *a = &col[(size_t)c * (size_t)(ld - 1)], t = a[0];
        a[0] = a[jp];
        a[jp] = t;
    }
}

/* LU of band in place with partial pivoting: LAPACK's dgbtf2 (what dgbtrf
 * runs for kl below its block size), written out as band_solve_kl is: its
 * per-column dger, dswap and dscal calls cost more than their arithmetic at
 * this size (29 % of the suture scene's time). The same storage (kv = 2 kl
 * rows above the diagonal, U's fill-in in the top kl), 1-based pivots, and
 * the first zero pivot's column + 1 returned as LAPACK's info.
 * The band is as wide as the widest coupling (kl = 14 while a puncture ties
 * four nodes) but most columns are narrower (the rod's own blocks reach 6
 * to 8 rows below the diagonal): each column's L is trimmed of its trailing
 * zeros before the pivot search and the update (which only skips products
 * with 0), and lower / upper record the profile for the solves. The factors
 * are the same numbers (suture.ini's CSV identical byte for byte); its 6 s
 * 6.6 % fewer instructions, bench_self_contact's knot 0.78x the time (its
 * Schur columns are band solves).
 * From column `from` on, the columns before it factored already (from > 0:
 * refresh_contact_jacobian), as the whole factorisation would factor them:
 * the columns from `from` on hold the matrix, and the steps before it whose
 * interchanges and updates reach them (at most 2 kl back) are applied to
 * them again from their pivots and L, then the steps go on from `from`. The
 * same operations on every entry in the same order as from 0, so the same
 * numbers. */
static inline __attribute__((always_inline)) int band_factor_kl(implicit_work *w, const int kl,
                                                               const int from)
{
    const int n = w->unknowns, kv = 2 * kl, ld = w->ldab;
    double *restrict ab = w->band;
    lapack_int *restrict pivot = w->pivot;
    int *restrict lower = w->lower, *restrict upper = w->upper;
    int info = 0, ju = 0;
    for (int j = from; j < n; j++) upper[j] = j; /* none above the diagonal yet */
    /* the fill-in rows of the first kl columns start at zero */
    for (int j = kl + 1 > from ? kl + 1 : from; j < kv && j < n; j++)
        for (int i = kv - j; i < kl; i++) ab[(size_t)j * ld + i] = 0.0;
    for (int j = 0; j < from; j++) { /* the steps before: their reach, and again on from.. */
        const int jp = pivot[j] - 1 - j;
        const int last = j + kl + jp < n - 1 ? j + kl + jp : n - 1;
        if (last > ju) ju = last;
        if (j + kv < n && j + kv >= from)
            for (int i = 0; i < kl; i++) ab[(size_t)(j + kv) * ld + i] = 0.0;
        if (ju < from) continue;
        double *col = &ab[(size_t)j * ld + kv];
        if (jp != 0) band_swap(col, jp, from - j, ju - j, ld);
        band_update(col, j, from - j, ju - j, lower[j], ld, upper);
    }
    for (int j = from; j < n; j++) {
        if (j + kv < n)
            for (int i = 0; i < kl; i++) ab[(size_t)(j + kv) * ld + i] = 0.0;
        int km = kl < n - 1 - j ? kl : n - 1 - j;
        double *col = &ab[(size_t)j * ld + kv]; /* col[i] = A(j + i, j) */
        while (km > 0 && col[km] == 0.0) km--;
        /* the loops over L run a fixed length of SHORT_COLUMN where km is
         * shorter and the band not narrower, over exact zeros past km (the same
         * numbers): the rod's own columns reach 6 to 8 rows down, and a loop
         * over km did not unroll or vectorise (5 % of suture.ini's time in
         * the solves) */
        const int len = kl >= SHORT_COLUMN && km < SHORT_COLUMN && j + SHORT_COLUMN < n
                            ? SHORT_COLUMN : km;
        lower[j] = len;
        int jp = 0;
        double big = fabs(col[0]);
        for (int i = 1; i <= km; i++)
            if (fabs(col[i]) > big) {
                big = fabs(col[i]);
                jp = i;
            }
        pivot[j] = j + jp + 1;
        if (col[jp] == 0.0) {
            if (info == 0) info = j + 1;
            continue;
        }
        const int last = j + kl + jp < n - 1 ? j + kl + jp : n - 1;
        if (last > ju) ju = last;
        if (jp != 0) band_swap(col, jp, 0, ju - j, ld); /* over columns j..ju */
        const double inv = 1.0 / col[0];
        for (int i = 1; i <= km; i++) col[i] *= inv;
        band_update(col, j, 1, ju - j, len, ld, upper); /* columns j+1..ju */
    }
    return info;
}

/* LU of band in place (band_factor_kl), its columns before `from`
 * factored already. Returns 0, or -1 when the matrix is singular. */
static int factor_band_from(implicit_work *w, double dt, int from)
{
    if (w->self) rod_self_contact_invalidate(w->self); /* its B^-1 V was for the old band */
    w->trail_valid = 0; /* until the caller records what these factors are of */
    const int nu = w->unknowns, kl = w->kl, ku = w->kl, ld = w->ldab;
    int info = w->kl == BAND ? band_factor_kl(w, BAND, from)
               : w->kl == BAND_PUNCTURE ? band_factor_kl(w, BAND_PUNCTURE, from)
                                        : band_factor_kl(w, BAND_PLANAR, from);
    w->jacobian_builds++;
    w->have_factor = (info == 0);
    w->jacobian_dt = dt;
    if (info == 0)
        for (int j = from; j < nu; j++) w->inv_diag[j] = 1.0 / w->band[(size_t)j * (size_t)ld + (size_t)(kl + ku)];
    return info == 0 ? 0 : -1;
}

static int factor_band(implicit_work *w, double dt)
{
    return factor_band_from(w, dt, 0);
}

/* Records the contact part just added to band_smooth and factored: the
 * base of the next renewal (refresh_contact_jacobian) */
static void trail_record(implicit_work *w, double dt)
{
    const size_t n = (size_t)w->nodes;
    memcpy(w->trail_jac, w->velocity_jac, n * 27 * sizeof(double));
    memcpy(w->trail_touched, w->touched, n);
    w->trail_dt = dt;
    w->trail_held[0] = w->ends[0].held, w->trail_held[1] = w->ends[1].held;
    w->trail_valid = 1;
}

/* The first unknown whose column or row contact's part changes since the
 * factors in band were made (trail_record), 0 when they cannot be reused,
 * or the number of unknowns when nothing changed. A touched node b's part
 * (add_contact_jacobian) lies in the rows of blocks b, b+1 and the columns
 * of blocks b-1 .. b+2; it is the same bit for bit when its velocity map,
 * its touch, the step and the ends' holds are (push and the coefficients
 * depend on nothing else). */
static int trail_first_change(const implicit_work *w, double dt)
{
    if (!w->trail_valid || w->smooth_kl != w->kl || dt != w->trail_dt ||
        w->trail_held[0] != w->ends[0].held || w->trail_held[1] != w->ends[1].held)
        return 0;
    const int n = w->nodes;
    for (int b = 0; b < n; b++) {
        const int now = w->touched[b] != 0, then = w->trail_touched[b] != 0;
        if (now != then || (now && memcmp(&w->velocity_jac[27 * b], &w->trail_jac[27 * b],
                                          27 * sizeof(double)) != 0)) {
            const int block = b - 1 - w->first;
            return block > 0 ? BLOCK * block : 0;
        }
    }
    return w->unknowns;
}

/* The rod's part of the Jacobian (contact and punctures left out by the
 * caller's contact_off): in closed form in 3-D (analytic_jacobian), by
 * finite differences in the plane (its cantilever is cheap) and in step's
 * retry (fd_only). Also while strands of the rod are candidates for
 * self-contact (their forces join in newton_solve, not in this part):
 * differences there cost 18 evaluations a Jacobian, and were kept once
 * because buckling_twist.ini's snap failed at 13.3 s with the closed form;
 * it now runs through (with the retry), in 28.5 s of CPU instead of 33.4,
 * overhand_tight.ini in 15.0 s instead of 20.2 (the same knot in every
 * frame, rope in the knot 19.7 diameters instead of 20.3), overhand.ini
 * and surgeons_knot.ini in 1.00x and 0.97x the time. */
static void rod_jacobian(implicit_work *w, const rod_model *m, double t, double dt)
{
    if (w->planar || w->fd_only) fd_jacobian(w, m, t, dt, 1);
    else analytic_jacobian(w, m, t, dt);
}

/* The Jacobian at the iterate x, factored. With contact: the rod's part
 * (rod_jacobian, the residual without contact), kept in band_smooth, and
 * the contact's part in closed form (add_contact_jacobian); in step's retry
 * (contact_fd) the whole by finite differences. Returns 0, or -1 when the
 * matrix is singular. */
static int factor_jacobian(implicit_work *w, const rod_model *m, double t, double dt)
{
    if (w->contact && !w->contact_fd) {
        /* the closed form reads only the frames of its evaluation, which
         * contact leaves alone; differences must leave contact out */
        w->contact_off = w->planar || w->fd_only;
        rod_jacobian(w, m, t, dt);
        w->contact_off = 0;
        memcpy(w->band_smooth, w->band, (size_t)w->ldab * (size_t)w->unknowns * sizeof(double));
        w->smooth_kl = w->kl, w->smooth_dt = dt, w->smooth_renewals = 0;
        add_contact_jacobian(w, m, t, dt, 0);
    } else {
        /* contact's friction turns within its creep speed (contact_creep_speed): a
         * step of 1e-7 of the force scale can move a node by more than that */
        const double step = w->fd_step;
        if (w->contact_fd) {
            w->fd_step = 1e-9;
            fd_jacobian(w, m, t, dt, w->reach);
        } else {
            rod_jacobian(w, m, t, dt);
        }
        w->fd_step = step;
    }
    w->stale = 0;
    if (factor_band(w, dt)) return -1;
    if (w->contact && !w->contact_fd) trail_record(w, dt); /* band_smooth + contact's part */
    return 0;
}

/* The contact's part alone renewed at the iterate x onto the kept
 * finite-difference part (the rod's own Jacobian changes slowly; which
 * nodes touch, stick or slip changes from one iterate to the next), and
 * factored. */
static int refresh_contact_jacobian(implicit_work *w, const rod_model *m, double t, double dt)
{
    /* Only from the first column contact's part changes: the factors'
     * columns before it stand as they are (trail_first_change,
     * band_factor_kl's `from`); suture.ini's renewals start on average 0.3
     * of the way along the thread, its tail on the skin changing least. */
    evaluate_iterate_once(w, m, t, dt);
    const int from = trail_first_change(w, dt), nu = w->unknowns;
    if (from == nu) { /* the factors are those of this Jacobian already */
        w->have_factor = 1;
        w->jacobian_dt = dt;
        return 0;
    }
    const size_t ld = (size_t)w->ldab;
    memcpy(&w->band[(size_t)from * ld], &w->band_smooth[(size_t)from * ld],
           ld * (size_t)(nu - from) * sizeof(double));
    add_contact_jacobian(w, m, t, dt, from);
    if (factor_band_from(w, dt, from)) return -1;
    trail_record(w, dt);
    return 0;
}

/* 1 when the factorisation made for dt_factored serves a step of dt.
 *
 * A relative tolerance, not equality: a caller that lands its steps on
 * output times passes dt = t_target - t, which differs from the step it
 * means by the rounding of t, a relative eps t/dt (2e-11 at t = 1e3 s,
 * dt = 1e-2 s; below 1e-9 up to 4e6 steps); exact equality rebuilt the
 * Jacobian at nearly every step. The Jacobian only steers Newton's
 * corrections (convergence is judged on the residual at the true dt), and
 * one made for dt (1 + delta) slows the iteration by a contraction of order
 * delta, invisible at delta = 1e-9.
 *
 * A real change of dt rebuilds, because the Jacobian cannot be rescaled
 * exactly: its dt-dependence is not affine in 1/dt. Per block, (3.14)'s
 * rows depend on N through dt^2 theta / (m w_b ds) (and on the damping
 * c dt / m, not affinely), (3.6)_2's rows on omega through w_b I / dt
 * (inertia), dt theta dM/dphi (elastic), and dt-free gyroscopic and damping
 * terms, and every elastic term is evaluated at the end frames
 * Q exp(dt omega_bar), nonlinear in dt. No scaling of rows and columns
 * maps one dt onto another (the four N/omega x constraint/momentum blocks
 * scale as dt^2, dt, 1 and dt + 1/dt), and the ratio of elastic to
 * inertial terms, (omega_n dt)^2, is the physics of the step. */
static int same_dt(double dt_factored, double dt)
{
    return fabs(dt - dt_factored) <= 1e-9 * fabs(dt);
}

/* Newton's correction dx = J^-1 r: the banded factors, and the self-contact
 * forces (unknowns beside x) by the Schur complement on them
 * (sim/self_contact.h). */
static void newton_solve(implicit_work *w, const rod_model *m, double dt)
{
    band_solve(w, w->dx);
    if (w->self && w->self->count)
        rod_self_contact_correct(w->self, w->dx, w->node_push, m->options.theta * dt / m->ds,
                                 band_solve_many, w);
}

/* N: what the self-contact pairs' residual is measured against, the force
 * scale or the largest force a pair's law asks for at the last evaluation,
 * if more (a strand pressed hard is held to the tolerance relative to its
 * force, as the difference quotients of its law allow) */
static double pair_scale(const implicit_work *w)
{
    return w->self && w->self->count ? fmax(w->force_scale, w->self->fmax) : w->force_scale;
}

/* The size of a residual whose scheme's part (scaled) is rod: the larger
 * of it and the pairs' (over scale, N) */
static double norm_with_pairs(const implicit_work *w, double rod, double scale)
{
    return w->self && w->self->count ? fmax(rod, w->self->gnorm / scale) : rod;
}

/* The size of the residual: the scheme's (scaled) and the pairs' (over
 * scale, N) */
static double residual_norm_at(const implicit_work *w, double scale)
{
    return norm_with_pairs(w, max_abs(w->residual, w->unknowns), scale);
}

/* A fingerprint of which self-contact pairs are active (their laws ask for
 * a force or they hold one) at the last evaluation */
static unsigned long active_pairs(const implicit_work *w)
{
    unsigned long h = 1469598103934665603ul;
    if (w->self)
        for (int q = 0; q < w->self->count; q++)
            if (w->self->pair[q].active) h = (h ^ (unsigned long)(q + 1)) * 1099511628211ul;
    return h;
}

/* Newton on one step; on success the iterate x holds the solution. */
static int newton(implicit_work *w, const rod_model *m, double t, double dt, rod_report *report)
{
    const int nu = w->unknowns;
    const double tol = m->options.newton_tolerance;
    const int max_it = m->options.newton_max_iterations;
    if (w->stale_start && w->contact && !w->contact_fd && !w->fd_only &&
        w->smooth_kl == w->kl && same_dt(w->smooth_dt, dt) &&
        w->smooth_renewals < CONTACT_START_REFRESHES) {
        /* stale at the last step: contact's part renewed at the first
         * iterate (CONTACT_START_REFRESHES) */
        if (refresh_contact_jacobian(w, m, t, dt)) return -1;
        w->smooth_renewals++;
        w->stale = 0;
    } else if (!w->have_factor || !same_dt(w->jacobian_dt, dt) ||
               (w->renew_pairs && w->self && w->self->count)) {
        if (factor_jacobian(w, m, t, dt)) return -1;
    }
    w->renew_pairs = 0;
    w->stale_start = 0;
    evaluate_iterate_once(w, m, t, dt);
    /* The pairs' residual is measured relative to the largest force their
     * laws ask for (residual_norm); within one iteration, the line search
     * compares the residual before and after on one scale, that of the
     * iterate it starts from. With each trial point's own scale, a trial
     * that raised some pair's force looked better than it was and one that
     * lowered it worse, so the search turned back from good steps (seen at
     * a plectoneme's snap). One scale: buckling_twist.ini 36.2 s of CPU
     * instead of 41.4 s, overhand.ini's first 8 s 13.7 instead of 14.1,
     * the same results within the tolerance */
    double scale = pair_scale(w), norm = residual_norm_at(w, scale);
    int fresh = 0; /* the factorisation was made at this step */
    int contact_fresh = 0; /* the contact's part was renewed at the last iteration */
    int rebuilt = 0;       /* whole Jacobians built at slow iterations of this attempt */
    double history[CONTACT_STALL]; /* the residual's norm at the last iterations */
    double recent[PAIRS_NONMONOTONE]; /* the same, for the line search (PAIRS_NONMONOTONE) */
    int rod_leads = 0, rod_led = 0; /* the scheme's residual the larger at the last iterates */
    for (int it = 0; it < max_it; it++) {
        report->newton_iterations = it;
        if (norm <= tol) {
            /* slow on an old B with strands touching (PAIRS_SLOW_STEP) */
            w->renew_pairs = w->self && w->self->count && it >= PAIRS_SLOW_STEP &&
                             w->self->b_age >= PAIRS_B_AGE && rod_led;
            return 0;
        }
        if (--w->budget < 0) return -1;
        w->newton_total++;
        memcpy(w->dx, w->residual, (size_t)nu * sizeof(double));
        const unsigned long active_before = active_pairs(w);
        newton_solve(w, m, dt);
        for (int i = 0; i < nu; i++) w->x[i] -= w->dx[i];
        if (w->self) rod_self_contact_move(w->self, -1.0);
        evaluate_iterate(w, m, t, dt);
        double next = residual_norm_at(w, scale);
        const int self_touch = w->self && w->self->count;
        /* the scheme's own residual at the full step (cut_alone, below) */
        const double rod_full = self_touch ? max_abs(w->residual, nu) : 0.0;
        double cut = 1.0; /* the fraction of the step the line search kept */
        const int contact = w->contact || self_touch;
        /* what a trial point must beat: the iterate's residual, or with
         * pairs touching the largest of it and the last PAIRS_NONMONOTONE */
        double bar = norm;
        if (self_touch)
            for (int j = 1; j <= PAIRS_NONMONOTONE && j <= it; j++)
                bar = fmax(bar, recent[(it - j) % PAIRS_NONMONOTONE]);
        recent[it % PAIRS_NONMONOTONE] = norm;
        if (contact && !(next < bar)) {
            /* contact makes the residual piecewise smooth: a full step can
             * jump across contacts that switch on or off, so back along it
             * until the residual falls (a line search; without contact the
             * full step is always taken) */
            double step = 1.0;
            for (int k = 0; k < 8 && !(next < bar); k++) {
                step *= 0.5;
                for (int i = 0; i < nu; i++) w->x[i] += step * w->dx[i];
                if (w->self) rod_self_contact_move(w->self, step);
                evaluate_iterate(w, m, t, dt);
                next = residual_norm_at(w, scale);
                if (--w->budget < 0) return -1;
            }
            cut = step;
        }
        if (!isfinite(next)) return -1;
        /* the scheme's own residual at the point kept */
        const double rod_now = max_abs(w->residual, nu);
        /* the iterate before this one left the scheme's residual above the
         * pairs' (PAIRS_SLOW_STEP) */
        rod_led = rod_leads;
        rod_leads = self_touch && rod_now >= w->self->gnorm / scale;
        /* the new iterate's own scale, taken before a rebuild below
         * (whose finite differences leave the pairs' laws unevaluated) */
        scale = pair_scale(w);
        const double next_norm = norm_with_pairs(w, rod_now, scale);
        if (next > IDLE_REFRESH_CONTRACTION * norm && next > tol) w->stale = 1;
        /* slow in the self-contact pairs' residual alone, or where a pair
         * switched on or off within the iteration: their laws are
         * linearised afresh at every iteration and B holds none of them, so
         * a new B would not help (a pair that starts touching within the
         * step joins the correction at the next iteration).
         * bench_self_contact's coil at NS = 201: 0.06 Jacobians per step
         * instead of 0.31; with the switches, its tight knot 5.5 instead of
         * 8.2, buckling_twist.ini 39 s of CPU instead of 51-64,
         * surgeons_knot.ini 20-21 instead of 25-26. Slow in the scheme's own
         * residual with strands touching, B is renewed up to twice per
         * attempt: a knot tightening or a rod snapping into a plectoneme
         * moves far within a step (buckling_twist.ini's snap at 12.3 s
         * stalled at a linear rate near 0.9 on a B made at the step's
         * second iterate, and converged on one made again). Slow only
         * because the line search cut the step, where the full step's own
         * residual of the scheme had fallen to a quarter (what rose was a
         * pair's, crossing friction's corner or parting) and the cut point
         * fell by 0.9 of what the linear model foresaw for it, B served
         * too: the sagging coil at NS = 201 renewed B 0.23 times a step
         * (28 times in its 120 steps, each followed by the pairs' columns
         * solved again: 4.2x the step without contact), with this 0.025
         * (2.3x); without the scheme's test at the full step,
         * buckling_twist.ini's snap stopped at 11.1 s */
        const int cut_alone = cut < 1.0 && rod_full <= 0.25 * norm &&
                              next <= (1.0 - 0.9 * cut) * norm;
        const int pairs_alone = self_touch && (rod_now <= 0.25 * norm ||
                                               active_pairs(w) != active_before || cut_alone);
        const double slow = w->contact && !self_touch ? CONTACT_SLOW_CONTRACTION : 0.25;
        if (next > slow * norm && next > 10.0 * tol && !pairs_alone &&
            (!fresh || w->contact || (self_touch && rebuilt < 2))) {
            /* slow, and not merely at the round-off floor near the tolerance:
             * a stale Jacobian; refresh it at the current iterate. With
             * contact, its part first (cheap: no finite differences); the
             * whole when that did not help at the last iteration, twice at
             * most: a thread turning as it lands needs the rod's part renewed
             * (test_contact's drop), while slowness beyond that is friction's
             * turn between stick and slip, which the rod's part does not
             * change (suture.ini: 19 s of CPU instead of 28 s without the
             * limit) */
            if (w->contact && !w->contact_fd && (!contact_fresh || rebuilt >= 2)) {
                if (refresh_contact_jacobian(w, m, t, dt)) return -1;
                contact_fresh = 1;
            } else {
                if (factor_jacobian(w, m, t, dt)) return -1;
                fresh = 1;
                rebuilt++;
            }
        } else {
            contact_fresh = 0;
        }
        norm = next_norm;
        if ((w->contact && !w->contact_fd) || (w->self && w->self->count)) {
            if (it >= CONTACT_STALL && norm > tol && !(norm <= 0.5 * history[it % CONTACT_STALL]))
                return -1;
            history[it % CONTACT_STALL] = norm;
        }
    }
    report->newton_iterations = max_it;
    return norm <= tol ? 0 : -1;
}

static void save_state(implicit_work *w, const rod_state *s)
{
    size_t n = (size_t)w->nodes;
    memcpy(w->save_frame, s->frame, n * 9 * sizeof(double));
    memcpy(w->save_pos, s->position, n * 3 * sizeof(double));
    memcpy(w->save_vel, s->velocity, n * 3 * sizeof(double));
    memcpy(w->save_omega, s->angular_velocity, n * 3 * sizeof(double));
    memcpy(w->save_force, s->contact_force, n * 3 * sizeof(double));
    memcpy(w->save_puncture, s->puncture, sizeof s->puncture);
    w->save_puncture_count = s->puncture_count;
    w->save_time = s->time;
}

static void restore_state(const implicit_work *w, rod_state *s)
{
    size_t n = (size_t)w->nodes;
    memcpy(s->frame, w->save_frame, n * 9 * sizeof(double));
    memcpy(s->position, w->save_pos, n * 3 * sizeof(double));
    memcpy(s->velocity, w->save_vel, n * 3 * sizeof(double));
    memcpy(s->angular_velocity, w->save_omega, n * 3 * sizeof(double));
    memcpy(s->contact_force, w->save_force, n * 3 * sizeof(double));
    memcpy(s->puncture, w->save_puncture, sizeof s->puncture);
    s->puncture_count = w->save_puncture_count;
    s->time = w->save_time;
}

/* One theta-method step without splitting. Returns 0 or -1 (no convergence). */
/* Planar start of a step from the state's frames: phi (unwrapped along the
 * rod so that u is continuous), and the z parts of the elastic state. */
static int begin_planar(implicit_work *w, const rod_model *m, const rod_state *s)
{
    const int n = w->nodes;
    for (int i = 0; i < n; i++) {
        const double *q = &s->frame[9 * i];
        if (fabs(q[8] - 0.0) > 1e-9 || fabs(q[7] - 1.0) > 1e-9) return -1; /* d2 must be +z */
        double phi = atan2(q[5], q[2]); /* d3 = (q2, q5, q8) */
        if (i > 0) phi = w->phi0[i - 1] + remainder(phi - w->phi0[i - 1], 2.0 * M_PI);
        w->phi0[i] = phi;
    }
    for (int j = 0; j + 1 < n; j++) {
        double mid = 0.5 * (w->phi0[j] + w->phi0[j + 1]);
        w->moment0[3 * j + 2] = m->stiffness[1] * (w->phi0[j + 1] - w->phi0[j]) / m->ds;
        w->d3mid0[3 * j] = cos(mid);
        w->d3mid0[3 * j + 1] = sin(mid);
        w->d3mid0[3 * j + 2] = 0.0;
    }
    return 0;
}

/* Planar end of a step: frames, strains, positions, velocities and forces
 * from phi1 and x, in the state's conventions; the next step's start. */
static void accept_planar(implicit_work *w, const rod_model *m, rod_state *s)
{
    const int n = w->nodes, nb = BLOCK_PLANAR;
    for (int i = 1; i < n; i++) {
        double c = cos(w->phi1[i]), sn = sin(w->phi1[i]);
        double *q = &s->frame[9 * i]; /* columns d1 = (-sn, c, 0), d2 = z, d3 = (c, sn, 0) */
        q[0] = -sn; q[1] = 0.0; q[2] = c;
        q[3] = c;   q[4] = 0.0; q[5] = sn;
        q[6] = 0.0; q[7] = 1.0; q[8] = 0.0;
    }
    for (int j = 0; j + 1 < n; j++) {
        double mid = 0.5 * (w->phi1[j] + w->phi1[j + 1]), c = cos(mid), sn = sin(mid);
        double u = (w->phi1[j + 1] - w->phi1[j]) / m->ds;
        v3_set(&s->darboux[3 * j], 0.0, u, 0.0);
        for (int k = 0; k < 3; k++)
            s->position[3 * (j + 1) + k] = s->position[3 * j + k] + m->ds * (k == 0 ? c : k == 1 ? sn : 0.0);
        const double *nx = &w->x[nb * j]; /* N_{j+1/2}, global x y */
        v3_set(&s->contact_force[3 * j], -sn * nx[0] + c * nx[1], 0.0, c * nx[0] + sn * nx[1]);
        w->moment0[3 * j + 2] = m->stiffness[1] * u;
        v3_set(&w->d3mid0[3 * j], c, sn, 0.0);
    }
    for (int b = 1; b < n; b++) {
        const double *xb = &w->x[nb * (b - 1)];
        double c = cos(w->phi1[b]), sn = sin(w->phi1[b]);
        v3_set(&s->velocity[3 * b], -sn * xb[2] + c * xb[3], 0.0, c * xb[2] + sn * xb[3]);
        v3_set(&s->angular_velocity[3 * b], 0.0, xb[4], 0.0);
    }
    memcpy(w->phi0, w->phi1, (size_t)n * sizeof(double));
}

/* The step's data of the held ends (from their paths; independent of the
 * Newton iterate) and the point loads' profile factor. */
static void prepare_ends(implicit_work *w, const rod_model *m, const rod_state *s, double dt)
{
    const int n = w->nodes;
    const double theta = m->options.theta, t = s->time;
    w->point_factor = theta * rod_profile_factor(&m->profile, t + dt) +
                      (1.0 - theta) * rod_profile_factor(&m->profile, t);
    for (int which = 0; which < 2; which++) {
        end_condition *e = &w->ends[which];
        const int node = which ? n - 1 : 0;
        if (!e->held) continue;
        const double *q0 = &s->frame[9 * node], *r0 = &s->position[3 * node];
        if (!e->have_initial || t == 0.0) {
            /* Q_end(0) = R(t)^T Q(t) at the first step, so the frame
             * follows R(t) Q_end(0) from wherever the run starts (again
             * when a state is reset to t = 0 for the same solver) */
            m3_identity(e->initial_frame);
            if (e->path) {
                rod_pose p0;
                rod_path_eval(e->path, t, &p0);
                m3_mul_tn(e->initial_frame, p0.rotation, q0);
            }
            v3_copy(e->anchor, r0);
            e->have_initial = 1;
        }
        v3_set(e->correction, 0.0, 0.0, 0.0);
        if (e->sliding) {
            double off[3];
            v3_sub(off, e->anchor, r0);
            v3_axpy(off, -v3_dot(off, e->slide), e->slide);
            v3_scale(e->correction, off, 1.0 / dt);
        }
        if (e->path) {
            rod_pose p1;
            rod_path_eval(e->path, t + dt, &p1);
            /* from the end's actual position: the step lands on the path
             * exactly, whatever rounding the chain of segments carried */
            for (int k = 0; k < 3; k++) e->vbar[k] = (p1.position[k] - r0[k]) / dt;
            v3_copy(e->vel1, p1.velocity);
            v3_copy(e->pos1, p1.position);
            if (e->clamped) {
                m3_mul(e->frame1, p1.rotation, e->initial_frame);
                m3_mul_tv(e->omega1, e->frame1, p1.angular_velocity);
            }
        } else {
            for (int k = 0; k < 3; k++) e->vbar[k] = (e->anchor[k] - r0[k]) / dt;
            v3_set(e->vel1, 0.0, 0.0, 0.0);
            v3_copy(e->pos1, e->anchor);
            if (e->clamped) {
                memcpy(e->frame1, q0, 9 * sizeof(double));
                v3_set(e->omega1, 0.0, 0.0, 0.0);
            }
        }
        if (e->clamped) {
            /* the frame at the theta point: the same rotation, scaled */
            double rel[9], phi[3], rot[9];
            m3_mul_tn(rel, q0, e->frame1);
            m3_log(phi, rel);
            v3_scale(phi, phi, theta);
            m3_exp(rot, phi);
            m3_mul(e->frame_th, q0, rot);
        }
    }
}

/* 1 when s is the state the last accepted step produced (its frames bit for
 * bit, at its time): the step's start-of-step quantities and the last two
 * solutions (the first iterate) carry over. The time within 1e-6 dt, not
 * equal: run_simulate sets t to the output time after a frame's steps (no
 * drift), which differs from the sum of the steps in the last bits, and an
 * exact test made every frame's first step start cold (suture.ini at
 * dt = 5 ms: 1681 cold starts in 3990 steps, 400 of them at frames;
 * refresh() skipped there too: suture_cantilever.ini 66 Jacobians instead
 * of 21). 1e-6 dt is far above that rounding (a few ulps of t) and far
 * below any real step. */
static int continues_from(const implicit_work *w, const rod_state *s, double dt)
{
    return w->start_valid && fabs(w->start_time - s->time) <= 1e-6 * dt &&
           memcmp(w->frame0, s->frame, (size_t)w->nodes * 9 * sizeof(double)) == 0;
}

/* Which extrapolation would have foreseen the solution x of the step of dt
 * just solved better, from the three before it (x_last, x_before,
 * x_before2, all of steps of dt): 2 for the parabola 3 (x_last - x_before)
 * + x_before2, 1 for the line 2 x_last - x_before (also when there are
 * fewer than three such steps). Each unknown's error is measured on its
 * kind's typical size (var_scale), summed in squares. The next step takes
 * the one that did better: where the motion is smooth the parabola's error
 * is O(dt^3) against the line's O(dt^2), while just after a contact
 * switches or a puncture is made the parabola carries the jump on for two
 * steps and the line for one. suture.ini: 63,191 Newton iterations instead
 * of 71,879 and 25,698 factorisations instead of 28,434, 0.93x the CPU
 * (1.97-2.03 s against 2.09-2.17 s, 3 paired runs; `make bench` 9.1-9.2x
 * real time instead of 8.5-8.6x); the parabola at every step: 63,429 and 26,606; a
 * cubic through four: fewer iterations (59,373), more factorisations
 * (27,030), more CPU than the parabola. Only with surfaces or punctures,
 * and not while self-contact pairs are candidates (single_step): there
 * it made the knots' runs 1.07x the CPU (the sum of the medians of 5
 * perturbed runs of overhand, overhand_tight, surgeons_knot and
 * buckling_twist: 36.3 s against 33.8 s), and without pairs
 * buckling_twist.ini, which touches no surface, 1.15x (13.5 s against
 * 11.7 s, 14,014 factorisations against 12,767: medians of 5). */
static int first_iterate_order(const implicit_work *w, double dt)
{
    if (!(w->dt_last > 0.0 && w->dt_before > 0.0) || !same_dt(w->dt_last, dt) ||
        !same_dt(w->dt_before, dt))
        return 1;
    double line = 0.0, parabola = 0.0;
    for (int i = 0; i < w->unknowns; i++) {
        const double scale = 1.0 / w->var_scale[w->var_kind[i % w->block]];
        const double el = (w->x[i] - (2.0 * w->x_last[i] - w->x_before[i])) * scale;
        const double eq =
            (w->x[i] - (3.0 * (w->x_last[i] - w->x_before[i]) + w->x_before2[i])) * scale;
        line += el * el;
        parabola += eq * eq;
    }
    return parabola < line ? 2 : 1;
}

/* The first iterate of a step that continues a run (single_step), mended
 * for the pairs' new shares. The pairs are found again at each step's
 * start, at fractions along their segments a little off the last step's,
 * or on the next segment when the strands slid across a node: a pair's
 * last force, its first guess, then lands on its nodes in other shares
 * (node a takes (1 - alpha) F, a + 1 alpha F), and the nodes' first
 * velocities are not those the last solution gave. Each node k's velocity
 * gains push_k (N_{k+1/2} - N_{k-1/2} + its share of F) (3.3)_1, push the
 * same for interior nodes, so N_{k+1/2} takes C_last(k) - C(k) of F, C(k)
 * the share of F on the nodes up to k (0 before segment a, 1 - alpha at
 * node a, 1 after): each node keeps the load the last solution gave it;
 * on the same segment, (alpha - alpha_last) F more in N_{a+1/2}; on
 * strand b the same with -F. Where overhand_tight.ini's knot held (t = 4
 * s), the first iterate's scaled residual was 3.5, in the constraint rows
 * of nodes a pair pressed with 10 N, and each step took 5 iterations;
 * with this, 5e-6 to 7e-7 and 1. `make bench`: the knot held 3.16x the
 * step without contact (38x), pulled tight 12.5x (30x); the sums of the
 * medians of 5 perturbed runs of the four knot scenes 12.7 s of CPU
 * against 15.3 (0.65x to 1.01x each). The solution is the same: only
 * where Newton starts moves */
static double share_up_to(int k, int segment, double fraction)
{
    return k < segment ? 0.0 : k == segment ? 1.0 - fraction : 1.0;
}

static void shift_strand(implicit_work *w, int seg, double frac, int seg_last, double frac_last,
                         double sign, const double force[3])
{
    const int lo = seg < seg_last ? seg : seg_last, hi = seg < seg_last ? seg_last : seg;
    for (int k = lo; k <= hi; k++) {
        const int b = k + 1; /* the block of N_{k+1/2} */
        const double c = share_up_to(k, seg_last, frac_last) - share_up_to(k, seg, frac);
        if (c != 0.0 && b >= w->first && b < w->nodes)
            v3_axpy(&w->x[w->block * (b - w->first)], sign * c, force);
    }
}

static void shift_for_pair_shares(implicit_work *w)
{
    const rod_self_contact *sc = w->self;
    for (int l = 0; l < sc->last_count; l++) {
        if (sc->last_to[l] < 0) continue;
        const self_pair *p = &sc->pair[sc->last_to[l]];
        const double *f = &sc->last_force[3 * l];
        shift_strand(w, p->a, p->alpha, sc->last_ab[2 * l], sc->last_frac[2 * l], 1.0, f);
        shift_strand(w, p->b, p->beta, sc->last_ab[2 * l + 1], sc->last_frac[2 * l + 1], -1.0, f);
    }
}

static int single_step(implicit_work *w, const rod_model *m, rod_state *s, double dt,
                       rod_report *report)
{
    const int n = w->nodes;
    /* start-of-step quantities; the previous step left them in place when the
     * state is the one it produced */
    int continuing = continues_from(w, s, dt);
    /* the step's own preparation below (its ends, punctures, contact):
     * no evaluation before it stands for this step's residual, not even
     * refresh()'s at the same state (live mode moves the driven end in
     * between) */
    w->eval_valid = 0;
    /* a factorisation the last step found stale is renewed at this step's
     * first iterate, before its slow iterations, unless refresh() did it
     * between the steps: newton() builds it, and its Jacobian's evaluation
     * of the iterate is also Newton's first residual (evaluated_at_x), one
     * evaluation fewer than refresh() and the step each making one
     * (suture.ini: 127,796 evaluations instead of 138,850, the results bit
     * for bit the same). As refresh(), not while self-contact pairs exist */
    w->stale_start = w->stale && !w->jacobian_only && continuing && w->dt_last > 0.0 &&
                     !(w->self && w->self->count);
    if (w->stale_start) w->have_factor = 0;
    if (!continuing) {
        memcpy(w->frame0, s->frame, (size_t)n * 9 * sizeof(double));
        elastic_state(m, w->frame0, w->darboux1, w->mid1, w->d3mid0, w->moment0);
        if (w->planar && begin_planar(w, m, s)) return -1;
        w->dt_last = 0.0;
        w->dt_before = 0.0;
    }
    w->start_valid = 0;
    memcpy(w->omega0, s->angular_velocity, (size_t)n * 3 * sizeof(double));
    for (int i = 0; i < n; i++) m3_mul_v(&w->vel0[3 * i], &s->frame[9 * i], &s->velocity[3 * i]);
    tip_load_global(m, s->time, &w->frame0[9 * (n - 1)], w->tipf0, w->tipm0);
    memcpy(w->pos0, s->position, (size_t)n * 3 * sizeof(double));
    prepare_ends(w, m, s, dt);
    prepare_punctures(w, m, s);
    if (w->surface_count) prepare_contact(w, m);
    if (w->max_reach == 2) {
        /* the wider band and its 5 colours only while a puncture couples two
         * nodes (ldab stays sized for it) */
        int reach = s->puncture_count > 0 ? 2 : 1;
        if (reach != w->reach) {
            w->reach = reach;
            w->kl = reach == 2 ? BAND_PUNCTURE : BAND;
            w->have_factor = 0;
        }
    }

    if (w->self && prepare_self_contact(w, m, dt,
                                        fmax(0.5 * m->diameter, fmin(SELF_MARGIN * m->diameter,
                                                                     3.0 * w->self_motion)),
                                        report))
        return -2;

    /* initial guess: the start-of-step values (N from the stored contact
     * force), or, continuing a run, the last solutions extrapolated: the
     * last two along a line, or the last three along a parabola when the
     * three steps had this dt and the parabola foresaw the last solution
     * better (first_iterate_order); while strands touch, the last solution
     * itself. Strands pressed together turn between stick and slip from one
     * step to the next, and a line through the last two solutions carries
     * each such turn on into the next step, doubled: where the tight knot
     * held (overhand_tight.ini at t = 4 s) the pairs' residual at the first
     * iterate was 2.3e-2 of their force scale along the line, 2.3e-4 from
     * the last solution (the rod's own about the same, 2.3-3.5).
     * The sums of the medians of 5 perturbed runs (dt (1 + k 1e-9), k = 0 to
     * 4) of overhand, overhand_tight, surgeons_knot and buckling_twist, with
     * friction's corner between strands (contact_creep_speed_corner): 24.2
     * s of CPU with the line, 19.3 with this (each scene 0.65x to 1.0x;
     * `make bench`'s knot pulled tight 0.98 Jacobians a step instead of
     * 6.2, 30x the step without contact instead of 118x) */
    if (continuing && w->dt_last > 0.0 && w->self && w->self->count) {
        memcpy(w->x, w->x_last, (size_t)w->unknowns * sizeof(double));
    } else if (continuing && w->dt_last > 0.0) {
        if (w->quadratic && same_dt(w->dt_last, dt) && same_dt(w->dt_before, dt)) {
            for (int i = 0; i < w->unknowns; i++)
                w->x[i] = 3.0 * (w->x_last[i] - w->x_before[i]) + w->x_before2[i];
        } else {
            double ratio = dt / w->dt_last;
            for (int i = 0; i < w->unknowns; i++)
                w->x[i] = w->x_last[i] + ratio * (w->x_last[i] - w->x_before[i]);
        }
    } else {
        for (int b = w->first; b < n; b++) {
            double *xb = &w->x[w->block * (b - w->first)], force[3] = {0.0, 0.0, 0.0};
            if (b > 0) m3_mul_v(force, &w->mid1[9 * (b - 1)], &s->contact_force[3 * (b - 1)]);
            if (w->planar) {
                xb[0] = force[0];
                xb[1] = force[1];
                xb[2] = w->vel0[3 * b];
                xb[3] = w->vel0[3 * b + 1];
                xb[4] = w->omega0[3 * b + 1];
            } else {
                v3_copy(xb, force);
                v3_copy(xb + 3, &w->omega0[3 * b]);
            }
        }
    }
    if (continuing && w->self && w->self->count) shift_for_pair_shares(w);
    if (w->fd_only)
        /* step's retry: a first iterate off any symmetry of the state, by
         * 1e-9 of each unknown's typical size, deterministically (test_live:
         * a straight thread lowered end-on onto a table has no straight
         * solution, and Newton from the straight guess stays on that line;
         * 1e-12 to 1e-3 all let it buckle there at first. Not always: at
         * stiffnesses 1e-8 to 1e-6 away, 1-2 lines still fail, kicks up to
         * 1e3 times larger alike; test_live now checks the level table for
         * what holds, and a tilted one for every line; scenes/README.md) */
        for (int i = 0; i < w->unknowns; i++)
            w->x[i] += 1e-9 * w->var_scale[w->var_kind[i % w->block]] * sin(1.0 + 0.7 * i);
    if (w->jacobian_only == 2) return 0; /* rod_implicit_jacobian_error: the first iterate */
    if (w->jacobian_only) return factor_jacobian(w, m, s->time, dt); /* refresh() */
    if (newton(w, m, s->time, dt, report)) return -1;
    for (int i = 0; i < w->unknowns; i++)
        if (!isfinite(w->x[i])) return -1; /* never accept a non-finite solution */
    if (w->self) {
        /* no pass-through: every pair that could have met within the step
         * must have been a candidate. Points move by at most `moved`, so two
         * segments farther apart than one diameter + 2 moved at the start
         * cannot touch on the way; a step that moved farther than the
         * candidates' margin allowed is solved again with a wider one. The
         * margin stays within SELF_MARGIN diameters: the pairs' contact is
         * linearised about the start (the half-space between the closest
         * points), which stands for the strands only near them, so a step
         * that would need more is split, unless no strand is near at all */
        double moved = largest_motion(w, dt);
        for (int tries = 0; tries < 4 && 2.0 * moved > w->self->margin; tries++) {
            if (3.0 * moved > SELF_MARGIN * m->diameter) {
                /* nothing that could touch within the step: no candidates
                 * needed (a straight stretch swinging fast moves its
                 * nearby segments together: rod_self_contact_reachable) */
                if (rod_self_contact_reachable(w->self, w->pos0, w->vbar, dt, 2.0 * moved) != 0) {
                    if (w->split_depth > w->motion_depth) w->motion_depth = w->split_depth;
                    return -1;
                }
                break;
            }
            if (prepare_self_contact(w, m, dt, 3.0 * moved, report)) return -2;
            if (newton(w, m, s->time, dt, report)) return -1;
            moved = largest_motion(w, dt);
        }
        if (2.0 * moved > w->self->margin && 3.0 * moved <= SELF_MARGIN * m->diameter) {
            if (w->split_depth > w->motion_depth) w->motion_depth = w->split_depth;
            return -1; /* split the step */
        }
        w->self_motion = moved;
        rod_self_contact_accept(w->self);
    }

    /* accept: Newton's last residual evaluation was at x, so frame1, darboux1,
     * d3mid1 and moment1 (or phi1 in the plane) describe the end of the step */
    if (w->planar) {
        accept_planar(w, m, s);
    } else {
        for (int i = 0; i < n; i++) {
            const end_condition *e = i == 0 ? &w->ends[0] : i == n - 1 ? &w->ends[1] : NULL;
            if (e && e->clamped) {
                memcpy(&s->frame[9 * i], e->frame1, 9 * sizeof(double));
                continue;
            }
            /* one Newton-Schulz step towards the nearest rotation,
             * Q <- Q (3 I - Q^T Q) / 2 (m3_orthonormalize takes two): Q is a
             * product of rotations, orthonormal to round-off, and the step
             * converges quadratically, so a second changes nothing */
            double qtq[9];
            const double *q = &w->frame1[9 * i];
            m3_mul_tn(qtq, q, q);
            for (int k = 0; k < 9; k++) qtq[k] *= -0.5;
            qtq[0] += 1.5; qtq[4] += 1.5; qtq[8] += 1.5;
            m3_mul(&s->frame[9 * i], q, qtq);
        }
        memcpy(s->darboux, w->darboux1, (size_t)(n - 1) * 3 * sizeof(double));
        /* centreline from d3 at the midpoints (3.12), as rod_positions_from_midframes,
         * from the held end where the step took it (the root when both are
         * held: the tip's own step returns it to its place) */
        const end_condition *root = &w->ends[0], *tip_end = &w->ends[1];
        if (root->held || !tip_end->held) {
            if (root->held && !root->sliding) v3_copy(s->position, root->pos1);
            else v3_axpy(s->position, dt, &w->vbar[0]);
            for (int j = 0; j + 1 < n; j++)
                for (int k = 0; k < 3; k++)
                    s->position[3 * (j + 1) + k] = s->position[3 * j + k] + m->ds * w->d3mid1[3 * j + k];
        } else {
            double *last = &s->position[3 * (n - 1)];
            if (!tip_end->sliding) v3_copy(last, tip_end->pos1);
            else v3_axpy(last, dt, &w->vbar[3 * (n - 1)]);
            for (int j = n - 2; j >= 0; j--)
                for (int k = 0; k < 3; k++)
                    s->position[3 * j + k] = s->position[3 * (j + 1) + k] - m->ds * w->d3mid1[3 * j + k];
        }
        for (int b = 0; b < n; b++) {
            const end_condition *e = b == 0 ? &w->ends[0] : b == n - 1 ? &w->ends[1] : NULL;
            m3_mul_tv(&s->velocity[3 * b], &s->frame[9 * b], &w->vel1[3 * b]);
            if (e && e->clamped) {
                v3_copy(&s->angular_velocity[3 * b], e->omega1);
            } else {
                const double *om = block_omega(w, w->x, b);
                for (int k = 0; k < 3; k++)
                    s->angular_velocity[3 * b + k] = (e && e->hold_omega[k]) ? 0.0 : om[k];
            }
            if (b == 0) continue;
            /* Q_mid^T N = exp(-h) Q_{b-1}^T N, h = ds/2 u, in the frame at the midpoint */
            double local[3], back[3];
            m3_mul_tv(local, &w->frame1[9 * (b - 1)], block_force(w, w->x, b));
            v3_scale(back, &w->darboux1[3 * (b - 1)], -0.5 * m->ds);
            v3_rotate(&s->contact_force[3 * (b - 1)], back, local);
        }
        end_reactions(w, m, s->time, dt);
        memcpy(s->surface_force, w->surface_force, (size_t)n * 3 * sizeof(double));
        if (w->self && w->self->count)
            memcpy(s->self_force, w->self->node_force, (size_t)n * 3 * sizeof(double));
        else
            memset(s->self_force, 0, (size_t)n * 3 * sizeof(double));
        update_punctures(w, m, s);
        if (w->needle_tissue && w->ends[1].held && needle_punctures(m, s, report)) return -2;
        memcpy(w->moment0, w->moment1, (size_t)(n - 1) * 3 * sizeof(double));
        memcpy(w->d3mid0, w->d3mid1, (size_t)(n - 1) * 3 * sizeof(double));
    }
    if (w->planar) {
        v3_set(&s->velocity[0], 0, 0, 0);
        v3_set(&s->angular_velocity[0], 0, 0, 0);
    }
    /* what the rod exerts on its supports: minus what they exert on it */
    for (int which = 0; which < 2; which++) {
        const end_condition *e = &w->ends[which];
        v3_scale(s->end_force[which], e->reaction, e->held ? -1.0 : 0.0);
        v3_scale(s->end_moment[which], e->reaction_moment, e->held ? -1.0 : 0.0);
    }
    /* tip entries (staggered convention): N(L) and B^-1 M(L) + u0, director
     * components; at a held tip the support's force and moment join the load */
    double f[3], mo[3];
    s->time += dt;
    tip_load_global(m, s->time, &s->frame[9 * (n - 1)], f, mo);
    if (w->ends[1].held) {
        v3_axpy(f, 1.0, w->ends[1].reaction);
        v3_axpy(mo, 1.0, w->ends[1].reaction_moment);
    }
    m3_mul_tv(&s->contact_force[3 * (n - 1)], &s->frame[9 * (n - 1)], f);
    m3_mul_tv(mo, &s->frame[9 * (n - 1)], mo);
    for (int k = 0; k < 3; k++)
        s->darboux[3 * (n - 1) + k] = mo[k] / m->stiffness[k] + m->intrinsic_curvature[k];
    /* the next step starts here */
    memcpy(w->frame0, s->frame, (size_t)n * 9 * sizeof(double));
    w->start_time = s->time;
    w->start_valid = 1;
    /* the last solution becomes the one before; a first step (dt_last = 0)
     * has no predecessor, so the next step cannot extrapolate yet */
    w->quadratic = continuing && w->contact && !(w->self && w->self->count) &&
                   first_iterate_order(w, dt) == 2;
    memcpy(w->x_before2, w->x_before, (size_t)w->unknowns * sizeof(double));
    memcpy(w->x_before, continuing ? w->x_last : w->x, (size_t)w->unknowns * sizeof(double));
    memcpy(w->x_last, w->x, (size_t)w->unknowns * sizeof(double));
    w->dt_before = continuing ? w->dt_last : 0.0;
    w->dt_last = continuing ? dt : 0.0;
    return 0;
}

static int split_step(implicit_work *w, const rod_model *m, rod_state *s, double dt,
                      rod_report *report, int depth)
{
    /* every attempt costs the budget at least one iteration, also one that
     * fails before Newton iterates (a singular Jacobian): the splits stay
     * bounded by the budget, not only by 2^MAX_SPLIT_DEPTH attempts, each
     * with a Jacobian build */
    if (--w->budget < 0) return -1;
    if (depth > w->deepest) w->deepest = depth;
    int rc = -1;
    if (depth >= w->start_depth) {
        w->split_depth = depth;
        rc = single_step(w, m, s, dt, report);
    } else {
        w->budget++; /* split without an attempt (SPLIT_HOLD_STEPS) */
    }
    if (rc == 0 || rc == -2) return rc; /* -2: no splitting helps (message set) */
    if (depth >= MAX_SPLIT_DEPTH || w->budget < 0) return -1;
    w->have_factor = 0;
    rc = split_step(w, m, s, 0.5 * dt, report, depth + 1);
    if (rc) return rc;
    w->have_factor = 0;
    return split_step(w, m, s, 0.5 * dt, report, depth + 1);
}

/* Where a step that did not converge left its residual largest (the last
 * attempt's last evaluation, w->residual): ", its residual largest in the
 * moment balance of node b (s = ... m)" and what touches the rod there
 * (within two nodes): a surface (its shape and scene line), a puncture or
 * another strand. Returns 1 when something touches it there. */
static int stall_site(const implicit_work *w, const rod_model *m, char *out, size_t len)
{
    out[0] = '\0';
    int worst = -1;
    double big = 0.0;
    for (int i = 0; i < w->unknowns; i++)
        if (isfinite(w->residual[i]) && fabs(w->residual[i]) > big) big = fabs(w->residual[i]), worst = i;
    if (worst < 0) return 0;
    const int n = w->nodes, node = worst / w->block + w->first, comp = worst % w->block;
    const char *what = w->planar ? "the balances of"
                       : comp < 3    ? "the length constraint (3.14) of the segment up to"
                                     : "the moment balance (3.6)_2 of";
    int used = snprintf(out, len, "; its residual stayed largest (%.2g) in %s node %d of %d "
                        "(s = %.4g m)", big, what, node, n, node * m->ds);
    /* a surface within a quarter diameter of a node at the step's start (the
     * last evaluation may have left contact out: a Jacobian's differences) */
    int touching = 0;
    static const int order[5] = {0, -1, 1, -2, 2}; /* the node itself first */
    for (int o = 0; o < 5 && w->surface_count && used > 0 && (size_t)used < len; o++) {
        const int i = node + order[o];
        if (i < 0 || i >= n) continue;
        int nearest = 0;
        const double *gap = &w->start_gap[7 * (size_t)i * (size_t)w->surface_count];
        for (int j = 1; j < w->surface_count; j++)
            if (gap[7 * j] < gap[7 * nearest]) nearest = j;
        if (!(gap[7 * nearest] < 0.25 * m->diameter)) continue;
        const rod_surface *sf = &w->surfaces[nearest];
        used += snprintf(out + used, len - (size_t)used, ", where node %d touches the %s of "
                         "line %d", i, rod_surface_name(sf->shape), sf->line);
        touching = 1;
        break;
    }
    for (int k = 0; k < w->puncture_count && used > 0 && (size_t)used < len; k++)
        if (w->punct[k].j >= node - 2 && w->punct[k].j <= node + 1) {
            used += snprintf(out + used, len - (size_t)used, ", beside the puncture at s = %.4g m",
                             (w->punct[k].j + w->punct[k].alpha) * m->ds);
            touching = 1;
            break;
        }
    if (w->self && used > 0 && (size_t)used < len)
        for (int i = node - 2; i <= node + 2; i++)
            if (i >= 0 && i < n && v3_norm(&w->self->node_force[3 * i]) > 0.0) {
                snprintf(out + used, len - (size_t)used, ", pressed by another strand of the rod");
                touching = 1;
                break;
            }
    return touching;
}

static rod_status unresolved(const rod_model *m, const rod_state *s, double angle, int segment,
                             rod_report *report)
{
    rod_unresolved_bend_message(m, "implicit", s->time, angle, segment, report->message,
                                sizeof report->message);
    return ROD_UNSTABLE;
}

static rod_status step(void *p, const rod_model *m, rod_state *s, double dt, rod_report *report)
{
    implicit_work *w = p;
    if (!(dt > 0.0) || !isfinite(dt)) {
        /* a programming error of the caller; refused rather than split 4096 ways */
        snprintf(report->message, sizeof report->message,
                 "implicit scheme: the step dt = %g s must be a positive finite time", dt);
        return ROD_FAILED;
    }
    if (s->time + dt == s->time) {
        /* below the rounding of t: the step would not advance the time, and a
         * loop stepping until t reaches a target would never end */
        snprintf(report->message, sizeof report->message,
                 "implicit scheme: the step dt = %g s is below the rounding of t = %.17g s and "
                 "would not advance the time; use a larger solver.dt", dt, s->time);
        return ROD_FAILED;
    }
    s->staggered = 1;
    save_state(w, s);
    /* rod_options.iteration_budget > 0: a caller's own, for each try */
    const int budget = m->options.iteration_budget > 0 ? m->options.iteration_budget
                                                       : STEP_ITERATION_BUDGET;
    w->budget = budget;
    w->deepest = 0;
    int segment;
    /* the depth the last steps' motion asked for (SPLIT_HOLD_STEPS) */
    w->start_depth = w->self && same_dt(w->depth_dt, dt) ? w->next_depth : 0;
    w->motion_depth = -1;
    int split = split_step(w, m, s, dt, report, 0), solved = split == 0;
    if (w->self) {
        int next = w->start_depth;
        if (w->motion_depth >= 0) {
            next = w->motion_depth + 1;
            w->depth_streak = 0;
        } else if (next > 0 && ++w->depth_streak >= SPLIT_HOLD_STEPS) {
            next--;
            w->depth_streak = 0;
        }
        w->next_depth = !solved ? 0 : next < MAX_SPLIT_DEPTH ? next : MAX_SPLIT_DEPTH - 1;
        w->depth_dt = dt;
    }
    w->start_depth = 0; /* the retries below from the whole step */
    for (int retry = 1; retry <= 2 && split == -1 && w->contact; retry++) {
        /* the step again, splits included, with a budget of its own: first
         * with the rod's part of the Jacobian by finite differences and a
         * first iterate off any symmetry (single_step), then the whole
         * Jacobian by differences, refreshed at every slow iteration (as
         * before the closed forms). A straight hanging thread lowered
         * end-on onto a table (test_live) has no solution that stays
         * straight, and the exact Jacobian, as symmetric as the thread,
         * keeps Newton on that line, its end pressed ever harder while the
         * compliance caps its sink */
        restore_state(w, s);
        w->fd_only = 1;
        w->contact_fd = retry == 2;
        w->have_factor = 0;
        w->budget = budget;
        split = split_step(w, m, s, dt, report, 0);
        solved = split == 0;
        w->contact_fd = 0;
        w->fd_only = 0;
        w->have_factor = 0;
    }
    report->jacobian_builds = w->jacobian_builds;
    report->newton_total = w->newton_total;
    if (split == -2) {
        restore_state(w, s);
        w->have_factor = 0;
        return ROD_FAILED;
    }
    if (solved) {
        double angle = rod_sharpest_bend(m, s->darboux, &segment);
        if (angle <= ROD_UNRESOLVED_BEND) return ROD_OK;
        return unresolved(m, s, angle, segment, report);
    }
    restore_state(w, s);
    w->have_factor = 0;
    double angle = rod_sharpest_bend(m, s->darboux, &segment);
    if (angle > 0.5 * ROD_UNRESOLVED_BEND) return unresolved(m, s, angle, segment, report);
    const int both_held = w->ends[0].held && !w->ends[0].sliding && w->ends[1].held &&
                          !w->ends[1].sliding;
    char site[256];
    const int contact_site = stall_site(w, m, site, sizeof site);
    /* at most 768 bytes (rod_report): a longer one loses its last words */
    const int written = snprintf(report->message, sizeof report->message,
             "implicit scheme: Newton's method did not converge at t = %.6g s for the step "
             "dt = %g s, split in halves down to dt/%d within %d iterations (tolerance %.1e)%s. "
             "%s%s",
             s->time, dt, 1 << w->deepest, budget, m->options.newton_tolerance,
             site,
             contact_site ? "Contact turning there between touching and not, or stick and slip, "
                            "can stall Newton at any step: a smaller dt may not help; change "
                            "the scene a little there (the shape, the surface, its friction)."
                          : "The load may change too abruptly for this dt, or exceed what the "
                            "rod can carry; try a smaller dt or a ramped load profile.",
             both_held && !contact_site
                 ? " Both ends hold their place: a nearly straight rod between them can "
                   "neither stretch nor shorten without bending, so its tension is "
                   "(nearly) undetermined; start it slightly bent (rod.shape, "
                   "rod.curvature) and let driven ends start from rest." : "");
    if (written >= (int)sizeof report->message) { /* cut at a word, not in one */
        char *end = strrchr(report->message, ' ');
        if (end) *end = '\0';
    }
    report->suggested_dt = dt / (1 << MAX_SPLIT_DEPTH);
    return ROD_NO_CONVERGENCE;
}

/* Between steps: a stale factorisation (IDLE_REFRESH_CONTRACTION) renewed
 * for the next step of dt from s, at that step's first iterate (the last
 * two solutions extrapolated), by that step's own preparation (single_step
 * up to newton), so that the step need not rebuild it on its own time
 * (live mode, between lines; a loop of steps leaves it to the step, which
 * then spares an evaluation: single_step).
 * Only when continuing a run of steps (single_step then reads s and leaves
 * it as it is; after a failed or restored step, the step builds its own)
 * and while the last step had no self-contact candidates (the pairs and
 * their forces are the step's own: none are sought here). */
static int refresh(void *p, const rod_model *m, const rod_state *s, double dt)
{
    implicit_work *w = p;
    if (!w->stale || (w->self && w->self->count) || !(dt > 0.0) || !(w->dt_last > 0.0) ||
        !continues_from(w, s, dt))
        return 0;
    rod_report report;
    memset(&report, 0, sizeof report);
    rod_self_contact *self = w->self; /* no pairs: it takes no part */
    w->self = NULL;
    w->jacobian_only = 1;
    int rc = single_step(w, m, (rod_state *)s, dt, &report); /* reads s only (above) */
    w->jacobian_only = 0;
    w->self = self;
    if (self) rod_self_contact_invalidate(self); /* its B^-1 V was for the old band */
    w->start_valid = 1; /* s as the last step left it: the next step continues from it */
    return rc == 0 ? 1 : -1;
}

/* rod_implicit_jacobian_error and rod_implicit_contact_jacobian_error:
 * with_contact 0 compares the rod's part (contact, punctures and the
 * pairs' laws left out, steps of 1e-4 of each unknown's size), 1 the whole
 * Jacobian Newton uses with surfaces and punctures (rod_jacobian +
 * add_contact_jacobian; the pairs' laws left out, they join through
 * rod_self_contact_correct), by steps of 1e-7: friction turns within its
 * creep speed, which a larger step would straddle */
static double jacobian_error(const rod_model *m, const rod_state *s, double dt, double perturb,
                             int with_contact, int *column, double *floor)
{
    if (floor) *floor = 0.0;
    char err[256];
    implicit_work *w = create(m, err, sizeof err);
    double worst = NAN;
    if (column) *column = -1;
    if (!w || w->planar) goto done;
    rod_report report;
    memset(&report, 0, sizeof report);
    w->jacobian_only = 2;
    if (single_step(w, m, (rod_state *)s, dt, &report)) goto done; /* reads s only */
    w->jacobian_only = 0;
    /* away from the start-of-step guess, deterministically, by `perturb`
     * of each unknown's typical size */
    for (int i = 0; i < w->unknowns; i++)
        w->x[i] += perturb * w->var_scale[w->var_kind[i % BLOCK]] * sin(1.0 + 0.7 * i);
    /* central differences, one column at a time (O(h^2), and no colouring:
     * independent of fd_jacobian's grouping and of its one-sided error) */
    const int nu = w->unknowns, kl = w->kl, ld = w->ldab;
    const size_t size = (size_t)ld * (size_t)nu;
    double *fd = calloc(size, sizeof(double)), *plus = malloc((size_t)nu * sizeof(double));
    double *x0 = malloc((size_t)nu * sizeof(double)), *step = malloc((size_t)nu * sizeof(double));
    if (!fd || !plus || !x0 || !step) {
        free(fd);
        free(plus);
        free(x0);
        free(step);
        goto done;
    }
    memcpy(x0, w->x, (size_t)nu * sizeof(double));
    w->contact_off = !with_contact;
    w->self_off = 1;
    const double relative = with_contact ? 1e-7 : 1e-4;
    for (int col = 0; col < nu; col++) {
        const double h = step[col] =
            relative * fmax(fabs(x0[col]), w->var_scale[w->var_kind[col % BLOCK]]);
        w->x[col] = x0[col] + h;
        evaluate(w, m, w->x, s->time, dt, plus);
        w->x[col] = x0[col] - h;
        evaluate(w, m, w->x, s->time, dt, w->perturbed);
        w->x[col] = x0[col];
        for (int row = col - kl; row <= col + kl; row++)
            if (row >= 0 && row < nu)
                fd[(size_t)(2 * kl + row - col) + (size_t)col * (size_t)ld] =
                    (plus[row] - w->perturbed[row]) / (2.0 * h);
    }
    free(plus);
    free(x0);
    w->contact_off = 1;
    analytic_jacobian(w, m, s->time, dt);
    w->contact_off = 0;
    if (with_contact && w->contact) add_contact_jacobian(w, m, s->time, dt, 0);
    w->self_off = 0;
    /* per entry, the differences' rounding, about 1e-16 of the residual's
     * O(1) terms over h, is not held against the closed form */
    worst = 0.0;
    for (int col = 0; col < nu; col++) {
        const double noise = 3e-16 / step[col];
        double big = 0.0, diff = 0.0;
        for (int r = 0; r < ld; r++) {
            const size_t k = (size_t)r + (size_t)col * (size_t)ld;
            big = fmax(big, fabs(fd[k]));
            diff = fmax(diff, fabs(fd[k] - w->band[k]) - noise);
        }
        double e = big > 0.0 ? diff / big : diff;
        if (floor && big > 0.0) *floor = fmax(*floor, noise / big);
        if (!(e <= worst)) {
            worst = e;
            if (column) *column = col;
        }
    }
    free(fd);
    free(step);
done:
    destroy(w);
    return worst;
}

double rod_implicit_rows_solve_check(const rod_model *m, const rod_state *s, double dt, int count,
                                     int first, long *differ)
{
    char err[256];
    implicit_work *w = create(m, err, sizeof err);
    double worst = NAN;
    *differ = -1;
    if (!w || w->planar || !w->rows || count < 1) goto done;
    rod_report report;
    memset(&report, 0, sizeof report);
    w->jacobian_only = 2;
    if (single_step(w, m, (rod_state *)s, dt, &report)) goto done; /* reads s only */
    w->jacobian_only = 0;
    w->contact_off = 1;
    analytic_jacobian(w, m, s->time, dt);
    w->contact_off = 0;
    const int nu = w->unknowns, kl = w->kl, ld = w->ldab;
    const size_t size = (size_t)ld * (size_t)nu, all = (size_t)nu * (size_t)count;
    double *a = malloc(size * sizeof(double)), *b = calloc(all, sizeof(double));
    double *x = malloc(all * sizeof(double)), *y = malloc(all * sizeof(double));
    if (a && b && x && y) {
        memcpy(a, w->band, size * sizeof(double));
        if (factor_band(w, dt) == 0) {
            /* right-hand sides zero above row `first`, as the pairs' are */
            for (int c = 0; c < count; c++)
                for (int i = first; i < nu; i++)
                    b[(size_t)c * (size_t)nu + (size_t)i] = sin(1.0 + 0.37 * i + 1.3 * c);
            memcpy(x, b, all * sizeof(double));
            memcpy(y, b, all * sizeof(double));
            band_solve_rows(w, x, count, first);
            for (int c = 0; c < count; c++) band_solve(w, &y[(size_t)c * (size_t)nu]);
            *differ = 0;
            for (size_t k = 0; k < all; k++) *differ += memcmp(&x[k], &y[k], sizeof(double)) != 0;
            /* |A x - b| over b's largest entry, A the matrix before its factors */
            worst = 0.0;
            for (int c = 0; c < count; c++) {
                const double *xc = &x[(size_t)c * (size_t)nu], *bc = &b[(size_t)c * (size_t)nu];
                for (int i = 0; i < nu; i++) {
                    double r = -bc[i];
                    for (int j = i - kl; j <= i + kl; j++)
                        if (j >= 0 && j < nu)
                            r += a[(size_t)(2 * kl + i - j) + (size_t)j * (size_t)ld] * xc[j];
                    worst = fmax(worst, fabs(r));
                }
            }
        }
    }
    free(a);
    free(b);
    free(x);
    free(y);
done:
    destroy(w);
    return worst;
}

double rod_implicit_jacobian_error(const rod_model *m, const rod_state *s, double dt,
                                   double perturb, int *column, double *floor)
{
    return jacobian_error(m, s, dt, perturb, 0, column, floor);
}

double rod_implicit_contact_jacobian_error(const rod_model *m, const rod_state *s, double dt,
                                           double perturb, int *column, double *floor)
{
    return jacobian_error(m, s, dt, perturb, 1, column, floor);
}

static double stable_dt(const rod_model *m, const char **limit)
{
    (void)m;
    if (limit) *limit = "implicit: unconditionally stable (no stability limit)";
    return INFINITY;
}

const rod_scheme_ops rod_scheme_implicit = {"implicit", create, step, destroy, stable_dt,
                                             refresh};
