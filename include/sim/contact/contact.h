/* contact.h: the implicit scheme's contact with the scene's surfaces and
 * with the punctures a thread passes through, over one step (the strands'
 * own contact: self_contact.h). The data the residual's laws read and
 * record (surface_contact.h, puncture.h), made once with the scheme's work.
 *
 * The node velocities are not Newton unknowns: the linear momentum balance
 * gives them from the iterate's forces, and a contact force F at node b
 * changes them by push F (push: the node's compliance over the step, m/s per
 * N). Given the iterate, each contact is a local problem solved in closed
 * form inside the residual, which corrects the velocities in place and, for
 * the Jacobian, records how each touched node's velocity after contact
 * depends on the free ones (velocity_jac). */
#ifndef RODSIM_SIM_CONTACT_CONTACT_H
#define RODSIM_SIM_CONTACT_CONTACT_H

#include "sim/rod_types.h"

/* One puncture of the step (from the state at its start; puncture_prepare) */
typedef struct contact_puncture {
    int j;             /* segment j..j+1 the thread passes the point through */
    double alpha;      /* fraction along it */
    double point[3], tangent[3], friction;
    double force[3];   /* N, global: what the tissue exerts on the thread, this iterate */
    double velocity[3];/* m/s, global: the point's own velocity (a grasp's jaws; 0 in tissue):
                          friction acts on the thread's velocity relative to it */
    double grip;       /* N: > 0: the friction's limit (a grasp), instead of friction
                          times the force across */
    double compliance[9]; /* m/N: an elastic pad's point moves by C times the force on it
                             (the point: where it is with that force removed); 0: rigid */
    int pad;           /* > 0: linked to that elastic pad (rod_puncture_state linked): its
                          law is solved with the pad's other punctures' */
    const double (*cross)[9]; /* the state's cross-compliances (rod_puncture_state cross,
                          m/N): the point moves by cross[l] times the force at puncture l;
                          NULL when not linked */
} contact_puncture;

typedef struct rod_contact {
    int nodes;
    int held[2];           /* 1: the root's (0) or the tip's (1) position is held: its
                              velocity is its support's, no contact moves it */
    double ds;             /* m: the uniform grid's segment length */
    const double *segment_length; /* the model's graded segment lengths (rod_grid.h); NULL on
                              a uniform grid */
    /* the scheme's arrays the laws read and correct (not owned) */
    const double *pos0;    /* (nodes x 3) global, m: positions at the start of the step */
    double *vel1, *vbar;   /* (nodes x 3) global, m/s: velocities at the end of the step and
                              their theta-mean over it */
    /* surfaces (surface_contact.h) */
    int surface_count;
    const rod_surface *surfaces; /* the model's */
    double *surface_force; /* (nodes x 3) global, N: what the surfaces exert, this iterate */
    double *start_gap;     /* (nodes x surfaces x 7): each node's gap (m), outward normal and
                              nearest point (m, global) at the start of the step: fixed over
                              the step, so found once, not in every residual; NULL without
                              surfaces */
    double *surface_motion; /* (nodes x surfaces x 8) at each node's nearest point at the
                              step's start: the surface's velocity (m/s, global), which the
                              friction acts relative to, its compliance (m/N; 0 rigid), and
                              the force the node put on it at its last equilibrium: across
                              (N) and along it (3, N, global); NULL when no surface moves
                              (only an elastic pad's does) */
    double *pad_force;     /* (nodes x 3) global, N: what an elastic pad's surface exerts
                              (its share of surface_force), this iterate; NULL without a pad */
    double *pad_last;      /* (2 x nodes x 3) global, N: pad_force of the last accepted step
                              (what the pad is loaded with), then the pad's own record of
                              what it was loaded with before (tissue_coupling_step); NULL
                              without a pad */
    unsigned *threaded;    /* (nodes): bit j set when the node is threaded through tissue
                              surface j (between its punctures): no contact with it */
    int needle_tissue;     /* 1: the driven tip carries a needle and a surface is tissue */
    /* instruments (sim/contact/instrument.h) */
    int instrument_count;
    double *instrument_start; /* (nodes x instruments x capsules x 10): each node's gap (m) to
                              each capsule at the step's start, its outward normal and the
                              capsule's point it faces at the step's end (m, global) and that
                              point's velocity (m/s); NULL without instruments */
    double *instrument_force; /* (nodes x 3) global, N: what the instruments exert, this
                              iterate; NULL without instruments */
    double *instrument_each;  /* (nodes x instruments x 3) global, N: the same by instrument
                              (for what each feels); NULL without instruments */
    int grasp_instrument[ROD_MAX_INSTRUMENTS]; /* the instrument of punct[puncture_count - grasps
                              + g] for each of this step's grasps */
    int grasp_count;
    /* punctures of this step (puncture.h), then the grasps (a point carried
     * by closed jaws: instrument.h), counted in puncture_count */
    int puncture_count;
    contact_puncture punct[ROD_MAX_PUNCTURES + ROD_MAX_INSTRUMENTS];
    /* the velocity maps, for the Jacobian (NULL when made without) */
    int want_jacobian;     /* 1: the laws record velocity_jac */
    double *velocity_jac;  /* (nodes x 27) for a touched node b: d v_b / d u_{b-1}, d v_b / d u_b,
                              d v_b / d u_{b+1} (row-major 3x3), v the end-of-step velocity
                              after contact, u the free one */
    unsigned char *touched;/* (nodes) 1: velocity_jac of the node is set (else the identity) */
} rod_contact;

/* Node i's compliance (m/s per N) from the interior's push = 1 / (ds (rho A
 * / dt + theta c)): push inside a uniform grid and 2 push at its ends (half
 * a cell), push ds / w_i on a graded grid, w_i node i's own cell
 * (rod_cell_length), as the residual's push_b. */
static inline double contact_node_push(const rod_contact *c, int i, double push)
{
    const int n = c->nodes;
    const double *sl = c->segment_length;
    if (!sl) return (i == 0 || i == n - 1) ? 2.0 * push : push;
    const double w = i == 0 ? 0.5 * sl[0] : i == n - 1 ? 0.5 * sl[n - 2] : 0.5 * (sl[i - 1] + sl[i]);
    return push * (c->ds / w);
}

/* Makes c for the model's surfaces and needle, reading and correcting the
 * scheme's arrays pos0, vel1 and vbar (nodes x 3, kept by the caller for
 * c's life); the velocity maps when `maps` is set. held: the ends' holds.
 * Returns 0, or -1 when out of memory (then rod_contact_destroy frees what
 * was made). */
int rod_contact_create(rod_contact *c, const rod_model *m, const double *pos0, double *vel1,
                       double *vbar, const int held[2], int maps);
void rod_contact_destroy(rod_contact *c);

/* Marks node b's velocity map as recorded, from the identity if it was not. */
void rod_contact_touch_node(rod_contact *c, int b);

#endif
