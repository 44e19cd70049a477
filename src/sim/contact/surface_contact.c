/* surface_contact.c: contact of the rod's nodes with the scene's surfaces
 * inside the implicit scheme's residual, and its velocity maps for the
 * Jacobian (surface_contact.h). */
#include "sim/contact/surface_contact.h"

#include <string.h>

#include "base/vec3.h"
#include "sim/contact/friction.h"
#include "sim/contact/mesh.h"
#include "sim/contact/surface.h"

/* How a swept contact's half-space turns with the node's velocity v
 * (surface_turn): the depth's gradient g (d e = (a / push) g.d v) and the
 * normal's Jacobian nn = d n / d v, with push lambda and vn = v'.n. */
typedef struct surface_turn {
    double g[3], nn[9], push_lambda, vn;
} surface_turn;

/* A node that did not touch at the step's start is held where its path
 * r0 -> r1 = r0 + dt vbar first enters the grown solid (surface_contact_node), at
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

/* Composes jac with the Jacobian of one surface's map in surface_contact_node,
 * v -> v + push F(v) (normal n, the tangential velocity vt after the normal
 * force, its norm speed and the friction's sp = contact_creep_speed(speed, c),
 * c = push mu lambda; stiff = d(e kappa/(1+kappa))/de, contact_compliant_slope):
 *   normal:   v' = v + push lambda n, d lambda / d v = -stiff / push g^T,
 *             so d v'/d v = A' = I - stiff n g^T + push lambda Nn; with the
 *             half-space held over the iteration (turn NULL: a node touching
 *             at the start, or a flat part) g = n and Nn = d n / d v = 0;
 *   friction: v'' = vn n + sp t (vn = v'.n, vt = v' - vn n = speed t), with
 *             d sp from contact_creep_slopes and d c / d v = -mu stiff g^T:
 *             d v'' = fric A' - d_c mu stiff t g^T + ((1 - ratio) n v'^T +
 *             vn ((1 - ratio) I + (ratio - d_speed) t t^T)) Nn,
 *             fric = n n^T + ratio (I - n n^T - t t^T) + d_speed t t^T,
 *             ratio = sp / speed. */
static void surface_map_jacobian(double jac[9], const double n[3], const double vt[3],
                                 double speed, double sp, double c, double mu, double stiff,
                                 double share, const surface_turn *turn)
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
        contact_creep_slopes(c, sp, &d_speed, &d_c);
        double ratio = speed > 0.0 ? sp / speed : d_speed;
        if (share < 1.0) {
            /* a compliant surface takes 1 - share of the friction's change
             * of the relative velocity: the node's is (1 - share) speed +
             * share sp along t (c's slope term is unchanged: share times
             * c's own scale push_t / push is 1) */
            ratio = (1.0 - share) + share * ratio;
            d_speed = (1.0 - share) + share * d_speed;
        }
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

void surface_contact_node(rod_contact *ct, const rod_model *m, int b, double push, double dt)
{
    double *v1 = &ct->vel1[3 * b], *vb = &ct->vbar[3 * b], *force = &ct->surface_force[3 * b];
    const double *r0 = &ct->pos0[3 * b];
    const double theta = m->options.theta, grow = 0.5 * m->diameter, a = dt * theta * push;
    v3_set(force, 0.0, 0.0, 0.0);
    double *pad_force = ct->pad_force ? &ct->pad_force[3 * b] : NULL;
    if (pad_force) v3_set(pad_force, 0.0, 0.0, 0.0);
    /* want_jacobian: jac = d v1 / d (v1 on entry), composed over the surfaces */
    double jac[9] = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
    /* a second pass only when two surfaces act on the node (a corner): one
     * surface's correction may push it into the other */
    int active = 0;
    for (int pass = 0; pass < 2 && (pass == 0 || active > 1); pass++)
        for (int j = 0; j < ct->surface_count; j++) {
            rod_surface view;
            const rod_surface *sf = rod_surface_contact_view(&ct->surfaces[j], &view);
            if (ct->threaded[b] & (1u << j)) continue;
            double r1[3], n[3], p[3], step[3];
            for (int k = 0; k < 3; k++) {
                step[k] = dt * vb[k];
                r1[k] = r0[k] + step[k];
            }
            const double *start = &ct->start_gap[7 * ((size_t)b * (size_t)ct->surface_count + (size_t)j)];
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
                curved = ct->want_jacobian && depth < 0.0 && rod_surface_curvature(sf, p, n, grow, hessian);
            }
            /* a compliant surface (an elastic pad): its point moves in by c
             * (lambda - lambda_last) under the force across lambda, c its
             * compliance, lambda_last what its last equilibrium carries, so
             * the depth against it is e = depth - c lambda_last and lambda =
             * -e / (a + c) (the pad's own give folded in, as a puncture's) */
            const double *motion = ct->surface_motion
                                       ? &ct->surface_motion[8 * ((size_t)b * (size_t)ct->surface_count + (size_t)j)]
                                       : NULL;
            const double give = motion ? motion[3] : 0.0;
            if (give > 0.0) depth -= give * motion[4];
            if (!(depth < 0.0)) continue;
            active++;
            double lambda = give > 0.0 ? -depth / (a + give) * contact_fraction(-depth, 0.01 * grow)
                                       : -depth / a * contact_fraction(-depth, 0.01 * grow),
                   fn[3], vt[3];
            v3_scale(fn, n, lambda);
            v3_axpy(v1, push, fn);
            v3_axpy(vb, theta * push, fn);
            v3_axpy(force, 1.0, fn);
            /* friction against the tangential velocity (contact_creep_speed),
             * relative to a moving surface's */
            double rel[3];
            v3_copy(rel, v1);
            if (motion) v3_axpy(rel, -1.0, motion);
            /* a compliant surface's point moves along by give times the
             * change of the friction on it over the step (against its last
             * equilibrium's, motion + 5): the relative velocity changes by
             * push_t = push (a + give) / a per newton of friction, the
             * node's own by push */
            const double push_t = give > 0.0 ? push * (a + give) / a : push;
            if (give > 0.0) v3_axpy(rel, -(push_t - push), motion + 5);
            double vn = v3_dot(rel, n);
            for (int k = 0; k < 3; k++) vt[k] = rel[k] - vn * n[k];
            double speed = v3_norm(vt), limit = sf->friction * lambda, ft[3] = {0.0, 0.0, 0.0}, sp = speed;
            if (speed > 0.0 && limit > 0.0) {
                sp = contact_creep_speed(speed, push_t * limit);
                v3_scale(ft, vt, -(speed - sp) / (push_t * speed));
                v3_axpy(v1, push, ft);
                v3_axpy(vb, theta * push, ft);
                v3_axpy(force, 1.0, ft);
            }
            if (pad_force && ct->surfaces[j].solid) {
                v3_axpy(pad_force, 1.0, fn);
                v3_axpy(pad_force, 1.0, ft);
            }
            if (ct->want_jacobian) {
                surface_turn turn;
                const int turning = curved && surface_turn_of(&turn, n, hessian, step, hit, a, push,
                                                              lambda, vn);
                double stiff = contact_compliant_slope(-depth, 0.01 * grow);
                if (give > 0.0) stiff *= a / (a + give);
                surface_map_jacobian(jac, n, vt, speed, sp, push_t * limit, sf->friction, stiff,
                                     give > 0.0 ? push / push_t : 1.0, turning ? &turn : NULL);
            }
        }
    if (ct->want_jacobian && active) {
        double *d = &ct->velocity_jac[27 * b];
        memset(d, 0, 27 * sizeof(double));
        memcpy(d + 9, jac, sizeof jac);
        ct->touched[b] = 1;
    }
}

void surface_contact_after_pairs(rod_contact *ct, const rod_model *m, const double *node_force,
                                 const double *push, double dt, double *node_map,
                                 unsigned char *mapped)
{
    const double theta = m->options.theta;
    for (int b = 0; b < ct->nodes; b++) {
        const double *f = &node_force[3 * b];
        if ((f[0] == 0.0 && f[1] == 0.0 && f[2] == 0.0) || push[b] == 0.0) continue;
        int punctured = 0;
        for (int q = 0; q < ct->puncture_count; q++)
            punctured |= b == ct->punct[q].j || b == ct->punct[q].j + 1;
        if (punctured) continue;
        double *sf = &ct->surface_force[3 * b];
        v3_axpy(&ct->vel1[3 * b], -push[b], sf);
        v3_axpy(&ct->vbar[3 * b], -theta * push[b], sf);
        if (ct->want_jacobian) ct->touched[b] = 0;
        surface_contact_node(ct, m, b, push[b], dt);
        if (ct->want_jacobian && ct->touched[b]) {
            memcpy(&node_map[9 * b], &ct->velocity_jac[27 * b + 9], 9 * sizeof(double));
            mapped[b] = 1;
        }
    }
}

void surface_contact_prepare(rod_contact *ct, const rod_model *m)
{
    const double grow = 0.5 * m->diameter;
    for (int b = 0; b < ct->nodes; b++)
        for (int j = 0; j < ct->surface_count; j++) {
            const size_t at = (size_t)b * (size_t)ct->surface_count + (size_t)j;
            double *start = &ct->start_gap[7 * at];
            rod_surface view;
            const rod_surface *sf = rod_surface_contact_view(&ct->surfaces[j], &view);
            start[0] = rod_surface_gap(sf, &ct->pos0[3 * b], grow, start + 1, start + 4);
            if (ct->surface_motion && ct->surfaces[j].solid && sf->mesh) {
                int t;
                double weights[3], *motion = &ct->surface_motion[8 * at];
                (void)rod_mesh_nearest(sf->mesh, &ct->pos0[3 * b], &t, weights);
                rod_mesh_point_velocity(sf->mesh, t, weights, motion);
                motion[3] = rod_mesh_point_compliance(sf->mesh, t, weights);
                /* what the last accepted step put on the pad */
                motion[4] = ct->pad_last ? v3_dot(&ct->pad_last[3 * b], start + 1) : 0.0;
                for (int k = 0; k < 3; k++)
                    motion[5 + k] = ct->pad_last ? ct->pad_last[3 * b + k] - motion[4] * start[1 + k] : 0.0;
            }
        }
}
