/*
 * Rest-to-rest eigenaxis slew guidance (docs/spec.md "Slew guidance", SPEC 5.1;
 * B. Wie, Space Vehicle Dynamics and Control, time-optimal and rate-limited
 * eigenaxis slews; H. Schaub, J. L. Junkins, Analytical Mechanics of Space
 * Systems, eigenaxis rotations).
 *
 * Planned once, when a target is commanded, from the attitude q0 at that time:
 *     dq = qd_f (x) q0^-1 (short way: dq4 >= 0),  theta_f = 2 atan2(|dq_vec|, dq4),
 *     e = dq_vec / |dq_vec|  (the eigenaxis, components in B at q0 = in D),
 * and evaluated in closed form from the time since the command (no drift):
 *     qd(t) = dq_e(theta(t)) (x) q0,  dq_e(theta) = [e sin(theta/2); cos(theta/2)],
 *     wd_D = thetadot(t) e,  wd_dot_D = thetaddot(t) e,
 * theta(t) a bang-coast-bang profile (accelerate at alpha, coast at the rate
 * limit if it is reached, decelerate at alpha) or its jerk-limited version
 * (the acceleration ramps linearly over jerk_time_s at each switch).
 * For t >= t_end the reference is exactly the commanded qd_f with zero rates.
 *
 * Envelope (one function per kind, so a wheel array can be added beside them):
 * along the slew the torque that the reference alone asks is
 *     u_ref = J wd_dot + wd x (J wd) = thetaddot a + thetadot^2 b0,
 *     a = J e, b0 = e x (J e),
 * with |thetaddot| <= alpha and thetadot^2 <= alpha theta_f for every
 * symmetric rest-to-rest profile whose acceleration is bounded by alpha
 * (the deceleration from the peak rate needs thetadot_pk^2 / (2 alpha) of the
 * remaining theta_f / 2). So u_ref stays in alpha * conv{+-a, +-a + b},
 * b = theta_f b0, and a convex envelope holds it whenever it holds those
 * four vertices. Each envelope function returns the largest alpha for which
 * it does; the profile flies alpha = margin * min over the set envelopes.
 * The rate limit only lowers the peak rate, so it keeps the bound.
 * The feedforward adds h_wheels (zero until a wheel array exists):
 *     u_ff = J wd_dot + wd x (J wd + h_wheels).
 *
 * Fixed size, no allocation; every function total; real_t float or double.
 */
#ifndef AOCS_GUIDANCE_SLEW_H
#define AOCS_GUIDANCE_SLEW_H

#include "aocs/attitude.h"
#include "aocs/actuation/wheel_array.h"
#include "aocs/math3.h"
#include "aocs/types.h"

typedef enum {
    AOCS_SLEW_PROFILE_BANG_COAST_BANG = 0, /* piecewise-constant acceleration */
    AOCS_SLEW_PROFILE_JERK_LIMITED,        /* linear acceleration ramps of jerk_time_s */
    AOCS_SLEW_PROFILE_COUNT
} aocs_slew_profile_t;

/* Longest accepted jerk ramp, s (a longer one is a unit mistake: the slews last minutes). */
#define AOCS_SLEW_JERK_TIME_MAX_S 1000u

typedef struct {
    aocs_slew_profile_t profile;
    real_t margin;            /* fraction of the envelope the reference may use, (0, 1] */
    real_t rate_limit_radps;  /* |wd| limit, rad/s, >= 0; 0 = none */
    real_t jerk_time_s;       /* ramp time, s: > 0 for JERK_LIMITED, 0 for BANG_COAST_BANG */
    aocs_mat3_t inertia_kgm2; /* J, kg m^2, symmetric positive definite */
} aocs_slew_config_t;

/* The body torque envelope (the executive's limits), N m. 0 = that kind unused. */
typedef struct {
    aocs_vec3_t u_max_axis_Nm; /* per-axis box; all 0 = unused */
    real_t u_max_norm_Nm;      /* |u|_2 ball; 0 = unused */
    const aocs_wheels_t *wheels; /* reaction wheel array (aocs_wheels_alpha_envelope); NULL = none */
} aocs_slew_envelope_t;

/* A planned slew (aocs_slew_plan). */
typedef struct {
    aocs_quat_t q0_BN;        /* attitude at the command */
    aocs_quat_t qf_DN;        /* commanded target */
    aocs_vec3_t e;            /* eigenaxis, unit */
    real_t theta_f_rad;       /* slew angle, [0, pi] */
    real_t accel_radps2;      /* peak acceleration flown (<= alpha) */
    real_t jerk_time_s;       /* ramp time (0: bang-coast-bang) */
    real_t hold_s;            /* time at the peak acceleration in each pulse */
    real_t pulse_s;           /* one acceleration pulse: hold + 2 ramps */
    real_t coast_s;           /* time at the peak rate */
    real_t rate_radps;        /* peak rate */
    real_t t_end_s;           /* end of the profile, from the command */
} aocs_slew_t;

/* Reference at one time (aocs_slew_eval); rates in D (= B0) components. */
typedef struct {
    aocs_quat_t qd_DN;
    aocs_vec3_t wd_D;         /* rad/s */
    aocs_vec3_t wd_dot_D;     /* rad/s^2 */
    real_t theta_rad;
    real_t theta_dot_radps;
    real_t theta_ddot_radps2;
} aocs_slew_ref_t;

/*
 * Config check, first failure wins: AOCS_ERR_NULL_ARG;
 * AOCS_ERR_GUIDANCE_PROFILE_INVALID (profile out of range);
 * AOCS_ERR_GUIDANCE_MARGIN_INVALID (margin not finite or outside (0, 1]);
 * AOCS_ERR_GUIDANCE_RATE_LIMIT_INVALID (not finite or < 0);
 * AOCS_ERR_GUIDANCE_JERK_TIME_INVALID (not finite, < 0, > AOCS_SLEW_JERK_TIME_MAX_S,
 * 0 with JERK_LIMITED or non-zero with BANG_COAST_BANG);
 * the inertia codes of aocs_mat3_check_inertia.
 */
aocs_status_t aocs_slew_config_check(const aocs_slew_config_t *cfg);

/*
 * Largest alpha (rad/s^2) such that alpha * {+-a, +-a + b} lie in the per-axis
 * box |u_i| <= u_max_i: min_i u_max_i / (|a_i| + |b_i|). Axes with
 * |a_i| + |b_i| == 0 do not bound it. AOCS_REAL_MAX when nothing bounds it. Total
 * (a NaN anywhere gives 0).
 */
real_t aocs_slew_alpha_box(aocs_vec3_t u_max_axis_Nm, aocs_vec3_t a, aocs_vec3_t b);

/* Same for the ball |u|_2 <= u_max: u_max / max(|a + b|, |a - b|). Total (NaN gives 0). */
real_t aocs_slew_alpha_norm(real_t u_max_norm_Nm, aocs_vec3_t a, aocs_vec3_t b);

/*
 * alpha_max(J, e, theta_f) of the envelope: the minimum over its set kinds
 * (a = J e, b = theta_f e x J e); 0 when no kind is set or on NaN. Total.
 */
real_t aocs_slew_alpha_max(const aocs_slew_envelope_t *env, aocs_mat3_t inertia_kgm2, aocs_vec3_t e,
                           real_t theta_f_rad);

/*
 * Plans the slew from q0_BN to qf_DN (both unit within AOCS_QUAT_UNIT_TOL; they
 * are normalised). AOCS_ERR_NULL_ARG; AOCS_ERR_QUAT_NOT_UNIT; the config's
 * status; AOCS_ERR_GUIDANCE_ENVELOPE_INVALID (no envelope set, or alpha not a
 * positive finite number). On error *slew is a zero-length slew at qf_DN (or
 * identity for a bad qf), so evaluating it is still defined.
 */
aocs_status_t aocs_slew_plan(aocs_slew_t *slew, const aocs_slew_config_t *cfg, const aocs_slew_envelope_t *env,
                             aocs_quat_t q0_BN, aocs_quat_t qf_DN);

/*
 * Reference at t_s seconds after the command (t < 0: the start at rest,
 * t >= t_end: qf_DN exactly, zero rates). Total: NULL args do nothing, a NaN t gives the start.
 */
void aocs_slew_eval(const aocs_slew_t *slew, real_t t_s, aocs_slew_ref_t *ref);

/* u_ff = J wd_dot + wd x (J wd + h_wheels), N m. Total. */
aocs_vec3_t aocs_slew_feedforward(aocs_mat3_t inertia_kgm2, aocs_vec3_t wd, aocs_vec3_t wd_dot,
                                  aocs_vec3_t h_wheels_Nms);

#endif /* AOCS_GUIDANCE_SLEW_H */
