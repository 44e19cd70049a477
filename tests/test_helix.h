/* test_helix.h: a rod at rest in a helix (its own intrinsic curvature), for
 * the self-contact test and bench: the last part of one turn and a bit lies
 * one pitch above the first. */
#ifndef RODSIM_TEST_HELIX_H
#define RODSIM_TEST_HELIX_H

#include <math.h>

#include "base/vec3.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"
#include "test_run_start.h"

/* A rod at rest in a helix of radius r and pitch P about +z from the
 * origin: intrinsic Darboux vector u0 = (kappa, 0, tau) (director
 * components; kappa = r w^2, tau = P w^2 / 2 pi, w^2 = 1 / (r^2 +
 * (P / 2 pi)^2)), frames Q(s) = Q0 exp(s [u0]x) with Q0 u0 along +z, and
 * the centreline chained from the midpoint frames as the scheme chains it
 * (helix_state: at the nodes' arc lengths s_i, each segment its own length
 * on a graded grid). One turn and `overlap` more: the last part lies P
 * above the first. */
static inline void helix_model(rod_model *m, double r, double P, double overlap, int nodes)
{
    const double w2 = 1.0 / (r * r + (P / (2.0 * M_PI)) * (P / (2.0 * M_PI)));
    const double kappa = r * w2, tau = P * w2 / (2.0 * M_PI);
    m->length = 2.0 * M_PI / sqrt(w2) + overlap;
    m->nodes = nodes;
    v3_set(m->intrinsic_curvature, kappa, 0.0, tau);
}

static inline void helix_state(const rod_model *m, rod_state *s)
{
    const double *u0 = m->intrinsic_curvature, a = atan2(u0[0], u0[2]);
    /* d2 = y; d1 = (cos a, 0, sin a), d3 = d1 x d2 = (-sin a, 0, cos a):
     * kappa d1 + tau d3 = |u0| z when tan a = kappa / tau */
    double q0[9] = {cos(a), 0.0, -sin(a), 0.0, 1.0, 0.0, sin(a), 0.0, cos(a)};
    v3_set(s->position, 0.0, 0.0, 0.0);
    for (int i = 0; i < m->nodes; i++) {
        double phi[3], rot[9];
        v3_scale(phi, u0, rod_node_arc(m, i));
        m3_exp(rot, phi);
        m3_mul(&s->frame[9 * i], q0, rot);
        v3_copy(&s->darboux[3 * i], u0);
        v3_set(&s->velocity[3 * i], 0.0, 0.0, 0.0);
        v3_set(&s->angular_velocity[3 * i], 0.0, 0.0, 0.0);
        if (i == 0) continue;
        const double ds = rod_segment_ds(m, i - 1);
        double half[3], hr[9], mid[9], d3[3];
        v3_scale(half, u0, 0.5 * ds);
        m3_exp(hr, half);
        m3_mul(mid, &s->frame[9 * (i - 1)], hr);
        m3_column(d3, mid, 2);
        for (int k = 0; k < 3; k++) s->position[3 * i + k] = s->position[3 * (i - 1) + k] + ds * d3[k];
    }
}

/* The self-contact tests' helix (D = 2 mm, E = 1 GPa, root clamped, self
 * friction 0.2) in m from rod_model_default(), not derived: a dead load
 * (0, 0, -force) at the tip after a ramp of t_ramp, or a pulse of it for
 * t_ramp when pulse is set; damping N s/m^2. */
static inline void helix_loaded(rod_model *m, double r, double P, double overlap, int nodes,
                                double force, double t_ramp, int pulse, double damping,
                                int self_contact)
{
    m->diameter = 0.002;
    m->density = 1100.0;
    m->youngs_modulus = 1e9;
    m->shear_modulus = 1e9 / 2.6;
    helix_model(m, r, P, overlap, nodes);
    m->tip_frame = ROD_FRAME_GLOBAL;
    v3_set(m->tip_force, 0.0, 0.0, -force);
    m->profile.kind = pulse ? ROD_PROFILE_PULSE : ROD_PROFILE_RAMP;
    m->profile.t1 = pulse ? 0.0 : t_ramp;
    m->profile.t2 = t_ramp;
    m->linear_damping = damping;
    m->self_contact = self_contact;
    m->self_friction = 0.2;
}

/* A state of the derived m at rest in its helix (helix_state) and the
 * solver for it; NULL (the reason printed) when either cannot be made. */
static inline rod_state *helix_start(const rod_model *m, rod_solver *solver)
{
    rod_state *s = run_start(m, solver);
    if (s) helix_state(m, s);
    return s;
}

/* The sagging coil of bench_self_contact and test_self_contact: one and a
 * half turns of radius 5 cm and pitch 1.01 D (D = 2 mm, E = 1 GPa, root
 * clamped, damping 0.02), under gravity along its axis: its last half turn
 * comes to lie on its first. m from rod_model_default(); returns
 * rod_model_derive's status (err set). */
static inline int sagging_coil(rod_model *m, int nodes, int self_contact, char *err, size_t errlen)
{
    m->diameter = 0.002;
    m->density = 1100.0;
    m->youngs_modulus = 1e9;
    m->shear_modulus = 1e9 / 2.6;
    helix_model(m, 0.05, 1.01 * m->diameter, M_PI * 0.05, nodes);
    m->linear_damping = 0.02;
    m->self_contact = self_contact;
    if (rod_model_derive(m, err, errlen)) return -1;
    v3_set(m->distributed_force, 0.0, 0.0, -9.81 * m->mass_per_length);
    return 0;
}

#endif
