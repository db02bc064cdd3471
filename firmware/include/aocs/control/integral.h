/*
 * Integral state of the laws with integral action (quat_pid, lqr_quat_i;
 * SPEC 5.2): conditional integration against the executive's limits and a
 * clamp, one implementation for both laws.
 *
 * Discretisation: forward Euler, z(k+1) = z(k) + dt e(k), the command of step
 * k using z(k). It is explicit (the saturation test below needs the command
 * before the update, so there is no algebraic loop), it is the integral of the
 * zero-order-held error the executive applies over the period, and with the
 * integral time constants of these laws (tens of seconds and more against
 * dt = 0.1 s) its phase lag of dt/2 is negligible.
 *
 * Anti-windup (conditional integration, Wie, Space Vehicle Dynamics and
 * Control, integrator windup; Markley & Crassidis 2014, PID attitude control): the law gives
 * its command u (before the executive's saturation) and the sensitivity
 * S = du/dz of u to its integral state (quat_pid: -ki I; lqr_quat_i: -K_z).
 * Component j of z is NOT advanced by dz_j = dt e_j when the increment
 * du = S[:, j] dz_j would push the command further into a limit it is at:
 *   per-axis limit (u_max_axis_i > 0): some axis i with |u_i| >= u_max_axis_i
 *       and u_i du_i > 0 (the increment grows the saturated component);
 *   norm limit (u_max_norm > 0): |u|_2 >= u_max_norm and u . du > 0. The
 *       executive scales the whole vector to the ball, so the delivered
 *       command's direction is u's and only its magnitude is limited:
 *       "saturated in the direction that would grow it" is an increment
 *       that grows |u| (d|u| = u . du / |u| > 0). An increment that turns u
 *       or shrinks it still integrates, since it changes what is delivered.
 * A limit of 0 is unused (law_io.h). After the update each component is
 * clamped to [-z_max, z_max].
 *
 * The test sees the law's own output only: a feedforward the executive adds
 * after the law (slew guidance) is not in u, so while the guidance takes a
 * share of the envelope the law may integrate although the sum saturates;
 * the clamp bounds what it can store then.
 */
#ifndef AOCS_CONTROL_INTEGRAL_H
#define AOCS_CONTROL_INTEGRAL_H

#include "aocs/math3.h"

/*
 * z(k+1) as above. e: the integrated error (s qe_vec); sens: S = du/dz
 * (N m per unit of z); u: this step's command before saturation; u_max_axis,
 * u_max_norm: the executive's limits (0 = unused); z_max > 0. Total: a
 * non-finite candidate component is not taken (z_j kept), and the result is
 * always within the clamp.
 */
aocs_vec3_t aocs_integral_update(aocs_vec3_t z, aocs_vec3_t e, real_t dt_s, aocs_mat3_t sens, aocs_vec3_t u,
                                 aocs_vec3_t u_max_axis, real_t u_max_norm, real_t z_max);

/*
 * 1 when the increment du would grow a command u that is at one of the limits
 * (the two rules above), else 0. Exposed for the tests.
 */
int aocs_integral_grows_saturation(aocs_vec3_t u, aocs_vec3_t du, aocs_vec3_t u_max_axis, real_t u_max_norm);

#endif /* AOCS_CONTROL_INTEGRAL_H */
