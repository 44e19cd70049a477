/* newton.h: Newton's method on one step of the implicit scheme, internal to
 * the implicit room: chord iterations on a factorisation of the Jacobian
 * (jacobian.h) reused across iterations and steps while it keeps
 * converging, renewed (contact's part first) when convergence slows; a line
 * search where contact makes the residual piecewise smooth; the strands'
 * pair forces join each correction by a Schur complement
 * (sim/contact/self_contact.h). */
#ifndef RODSIM_SIM_IMPLICIT_NEWTON_H
#define RODSIM_SIM_IMPLICIT_NEWTON_H

#include "sim/implicit/work.h"

/* The iterations a patient attempt (w->patient: the step's last retry, and
 * the steps held patient after it) allows, with no stall test, as a
 * multiple of solver.newton_max_iterations (25 by default: 100), so that
 * key still bounds every attempt's work. A rope on a
 * floor under strands piled on it turns some nodes between stick and slip
 * at most iterations, and the line search cuts the step to 1/8 - 1/16 for
 * ten or more of them before Newton settles (20 - 95 iterations at the
 * step's own dt); the halves a stall splits into are worse: a resting
 * node's sink over a step (g dt^2) falls below the iterates' error, and
 * every other node of the strand on the floor turns between touching and
 * not (docs/decisions/0072-pile-planar.md) */
#define PATIENT_FACTOR 4

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
int implicit_same_dt(double dt_factored, double dt);

/* Newton on the step t -> t + dt from the first iterate in x, within the
 * step's budget of iterations (w->budget); on success (0) x holds the
 * solution; -1 when it does not converge (the caller splits the step).
 * With w->patient: up to PATIENT_FACTOR times as many, no stall test; sets
 * w->patience_used when it went past either.
 * report->newton_iterations: the iterations taken. */
int implicit_newton(implicit_work *w, const rod_model *m, double t, double dt, rod_report *report);

#endif
