/*
 * Reaction wheel array: configuration, minimum-norm torque allocation with a
 * uniform scale, speed-limit protection, total momentum and the guidance's
 * acceleration envelope (docs/spec.md 5.3; Schaub & Junkins ch. 4; Wie ch. 7).
 *
 *   aocs_wheels_init(&wa, &cfg);               validates, computes Gs^+ once
 *   aocs_wheels_allocate(&wa, u_c_B, omega, &alloc);   every control step
 *   aocs_wheels_momentum(&wa, w_BN_B, omega, &mom);    H and the margins
 *   aocs_wheels_alpha_max(&wa, J, e);          guidance envelope along e
 *
 * Friction feedforward and null-space speed management (docs/spec.md 5.3.2):
 * the allocation computes the net axial torque each wheel must apply,
 * tau = -Gs^+ u_c, and commands the motor u_s = s tau + r u_n + f^(Omega):
 * f^ is the bearing friction model of the plant (viscous b, Coulomb c
 * smoothed by tanh(Omega / Omega_eps)) evaluated at the tachometer speed, so
 * the friction no longer reaches the body; u_n = k_n P_N Js (Omega* - Omega)
 * drives the null-space part of the wheel momenta toward the targets Omega*
 * (P_N = I - Gs^+ Gs over the healthy wheels: -Gs u_n = 0, no body torque),
 * keeping the wheels away from the zero crossings where the Coulomb term is
 * steepest. The scales s (body torque, first) and r (null-space torque, in
 * what is left) are uniform, so neither changes a direction, and the motor
 * torque stays within u_s,max with the compensation included.
 *
 * Fixed size (AOCS_WHEELS_MAX wheels), no dynamic memory. The spin axes g_i
 * are the columns of Gs (3 x N) in B. The motors' reaction on the body is
 * -Gs u_s, so the body torque u_c is delivered by u_s = -Gs^+ u_c with
 * Gs^+ = Gs^T (Gs Gs^T)^-1 over the healthy wheels (a failed wheel's row is
 * zero: it is removed from the allocation).
 */
#ifndef AOCS_WHEEL_ARRAY_H
#define AOCS_WHEEL_ARRAY_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/math3.h"

#define AOCS_WHEELS_MAX 6u   /* largest array (a 6-wheel skew configuration) */
#define AOCS_WHEELS_MIN 3u   /* three wheels at least to control three axes */

/* A tachometer speed with |Omega| above this multiple of the wheel's speed limit Omega_max (or not finite)
 * is not a physical reading: the allocation and the momentum reject it (AOCS_ERR_WHEEL_SPEED_RANGE,
 * docs/spec.md 5.3.3). The speed protection keeps |Omega| below Omega_max; twice leaves room for any
 * overshoot and tachometer noise a real wheel shows. */
#define AOCS_WHEEL_SPEED_RANGE_FACTOR AOCS_R(2.0)

typedef struct {
    uint32_t n;                                /* wheels configured, AOCS_WHEELS_MIN .. AOCS_WHEELS_MAX */
    aocs_vec3_t axis_B[AOCS_WHEELS_MAX];       /* unit spin axis g_i in B */
    real_t js_kgm2[AOCS_WHEELS_MAX];           /* spin inertia Js_i, kg m^2, > 0 */
    real_t u_max_nm[AOCS_WHEELS_MAX];          /* motor torque limit u_s,max,i, N m, > 0 */
    real_t omega_max_radps[AOCS_WHEELS_MAX];   /* speed limit Omega_max,i, rad/s, > 0 */
    uint32_t failed_mask;                      /* bit i set: wheel i declared failed (removed) */
    real_t period_s;                           /* control period, s (> 0): horizon of the speed protection */
    aocs_mat3_t inertia_B_kgm2;                /* J of the spacecraft with its wheels (for H), valid inertia */
    /* bearing friction model of the feedforward, f(Omega) = b Omega + c tanh(Omega / Omega_eps) (spec 5.3.2) */
    real_t viscous_nms[AOCS_WHEELS_MAX];       /* b_i, N m s/rad, >= 0 (0: none) */
    real_t coulomb_nm[AOCS_WHEELS_MAX];        /* c_i, N m, >= 0 (0: none); b_i Omega_max,i + c_i < u_s,max,i */
    real_t coulomb_width_radps[AOCS_WHEELS_MAX]; /* Omega_eps,i, rad/s, > 0 */
    /* null-space wheel speed management (spec 5.3.2) */
    real_t null_gain_per_s;                    /* k_n, 1/s, >= 0 (0: none), k_n period_s <= 1 */
    real_t null_speed_radps[AOCS_WHEELS_MAX];  /* Omega*_i, target speeds, |Omega*_i| < Omega_max,i */
} aocs_wheels_config_t;

typedef struct {
    aocs_wheels_config_t cfg;
    real_t pinv[AOCS_WHEELS_MAX][3];           /* Gs^+ over the healthy wheels; zero rows for failed ones */
    real_t null_proj[AOCS_WHEELS_MAX][AOCS_WHEELS_MAX]; /* P_N = D_h - Gs^+ Gs_h, zero rows / columns for failed */
    uint32_t n_healthy;
    int initialised;
} aocs_wheels_t;

typedef struct {
    real_t u_s_nm[AOCS_WHEELS_MAX];            /* wheel motor torque commands, N m (0 for failed / unused) */
    real_t friction_nm[AOCS_WHEELS_MAX];       /* friction feedforward f^(Omega_i) included in u_s, N m */
    real_t null_nm[AOCS_WHEELS_MAX];           /* null-space torque r u_n included in u_s, N m */
    aocs_vec3_t u_body_B_nm;                   /* body torque they deliver, -Gs (u_s - f^) = scale * u_c */
    real_t scale;                              /* uniform scale applied, in [0, 1] (1: none) */
    real_t null_scale;                         /* r, uniform scale of the null-space torque, in [0, 1] */
    uint32_t torque_limited_mask;              /* bit i: wheel i's torque limit set the scale */
    uint32_t speed_limited_mask;               /* bit i: wheel i's speed headroom set the scale */
} aocs_wheels_alloc_t;

typedef struct {
    aocs_vec3_t h_total_B_Nms;                 /* H = J w + sum Js_i g_i Omega_i, B */
    real_t h_wheels_norm_Nms;                  /* |sum Js_i g_i Omega_i| */
    real_t speed_margin;                       /* min over healthy wheels of 1 - |Omega_i| / Omega_max,i */
    uint32_t worst_wheel;                      /* the wheel with that smallest margin */
} aocs_wheels_momentum_t;

/* Defaults: zero wheels (invalid until filled), period 0.1 s, identity inertia, no friction model
 * (b = c = 0, Omega_eps = 0.1 rad/s), no null-space management (k_n = 0, Omega* = 0). Total (no-op on NULL). */
void aocs_wheels_config_default(aocs_wheels_config_t *cfg);

/*
 * Validates cfg and computes Gs^+ over the healthy wheels. Status, the first
 * failed check in this order: AOCS_ERR_NULL_ARG; AOCS_ERR_WHEEL_COUNT (n out
 * of [3, 6]); AOCS_ERR_WHEEL_FAILED_MASK (a failed bit at or beyond n);
 * AOCS_ERR_WHEEL_AXIS_NOT_UNIT (axis not finite or | |g| - 1 | > 1e-4);
 * AOCS_ERR_WHEEL_INERTIA_NOT_POSITIVE (Js not finite or <= 0);
 * AOCS_ERR_WHEEL_LIMIT_NOT_POSITIVE (u_s,max or Omega_max not finite or <= 0);
 * AOCS_ERR_DT_INVALID (period); the inertia's own check
 * (aocs_mat3_check_inertia); AOCS_ERR_WHEELS_NOT_SPANNING (fewer than 3
 * healthy wheels, or det(Gs Gs^T) < 1e-6 for unit axes: the healthy wheels do
 * not span the three body axes); then the friction model per wheel:
 * AOCS_ERR_WHEEL_FRICTION_NEGATIVE (b or c not finite or < 0),
 * AOCS_ERR_WHEEL_FRICTION_WIDTH_NOT_POSITIVE (Omega_eps not finite or <= 0),
 * AOCS_ERR_WHEEL_FRICTION_EXCEEDS_LIMIT (b Omega_max + c >= u_s,max: the
 * compensation could take the whole motor); then the null-space management:
 * AOCS_ERR_WHEEL_NULL_GAIN_INVALID (k_n not finite, < 0 or k_n period > 1),
 * AOCS_ERR_WHEEL_NULL_SPEED_INVALID (a target not finite or |Omega*_i| >=
 * Omega_max,i). On error wa is left not initialised.
 */
aocs_status_t aocs_wheels_init(aocs_wheels_t *wa, const aocs_wheels_config_t *cfg);

/*
 * tau = -Gs^+ u_c (minimum norm: the net axial torques), then one uniform
 * scale s = max{s in [0, 1]: s tau_i in [lo_i, hi_i] for every wheel} so the
 * delivered body torque -Gs (s tau) = s u_c keeps its direction. [lo_i, hi_i]
 * is what wheel i's net torque may be this step: the motor limit with the
 * friction feedforward included, [-u_s,max - f^_i, u_s,max - f^_i], and
 * toward a higher speed at most the headroom Js_i (Omega_max,i - |Omega_i|) / T
 * (>= 0): no command drives a wheel beyond Omega_max within the period T.
 * Then the null-space torque u_n (k_n > 0) scaled by the largest r in [0, 1]
 * that keeps s tau_i + r u_n,i in [lo_i, hi_i], and u_s = s tau + r u_n + f^.
 * With b = c = 0 and k_n = 0 this is u_s = s (-Gs^+ u_c).
 * omega_radps: tachometer speeds relative to the body (n entries).
 * AOCS_ERR_NULL_ARG; AOCS_ERR_NOT_INITIALISED; AOCS_ERR_INPUT_NOT_FINITE (u_c
 * or a speed not finite). On any error *out is a zero command, scale 0.
 */
aocs_status_t aocs_wheels_allocate(const aocs_wheels_t *wa, aocs_vec3_t u_c_B, const real_t *omega_radps,
                                   aocs_wheels_alloc_t *out);

/*
 * The tachometer readings of the array's n wheels (rad/s, relative to the
 * body) are a physical measurement: AOCS_OK when every one is finite and
 * |Omega_i| <= AOCS_WHEEL_SPEED_RANGE_FACTOR Omega_max,i (docs/spec.md 5.3.3);
 * AOCS_ERR_INPUT_NOT_FINITE, AOCS_ERR_WHEEL_SPEED_RANGE otherwise;
 * AOCS_ERR_NULL_ARG; AOCS_ERR_NOT_INITIALISED.
 */
aocs_status_t aocs_wheels_check_speeds(const aocs_wheels_t *wa, const real_t *omega_radps);

/*
 * u_nm clamped to exactly [-u_max_nm, u_max_nm] (u_max_nm > 0); 0 for a NaN.
 * The last step of every wheel motor command (docs/spec.md 5.3.3). Total.
 */
real_t aocs_wheels_clamp_cmd(real_t u_nm, real_t u_max_nm);

/*
 * Total momentum and the margins to the speed limits (healthy wheels).
 * AOCS_ERR_NULL_ARG; AOCS_ERR_NOT_INITIALISED; AOCS_ERR_INPUT_NOT_FINITE
 * (*out zeroed on error).
 */
aocs_status_t aocs_wheels_momentum(const aocs_wheels_t *wa, aocs_vec3_t w_BN_B, const real_t *omega_radps,
                                   aocs_wheels_momentum_t *out);

/*
 * Guidance envelope of the wheel kind (docs/spec.md 5.1, 5.3): the largest
 * acceleration a along the unit axis e for which the body torque J a e is
 * delivered without scaling, a = min_i u_s,max,i / |(Gs^+ J e)_i| over the
 * healthy wheels. 0 when wa is NULL or not initialised, or any input not
 * finite, or J e = 0. Total.
 */
real_t aocs_wheels_alpha_max(const aocs_wheels_t *wa, aocs_mat3_t j_B_kgm2, aocs_vec3_t e_B);

/*
 * The wheel kind of the slew guidance's envelope functions (guidance/slew.h):
 * the largest alpha such that the allocation of every torque of
 * alpha * conv{+-a, +-a + b} stays within the wheels' torque limits without
 * scaling: min_i u_s,max,i / (|(Gs^+ a)_i| + |(Gs^+ b)_i|) over the healthy
 * wheels (|.| of a linear map is convex: the maximum is at a vertex).
 * aocs_wheels_alpha_max is this with a = J e, b = 0. AOCS_REAL_MAX when no
 * wheel is loaded; 0 when wa is NULL or not initialised or on NaN. Total.
 */
real_t aocs_wheels_alpha_envelope(const aocs_wheels_t *wa, aocs_vec3_t a, aocs_vec3_t b);

/*
 * The friction model of wheel i at speed omega (docs/spec.md 5.3.2):
 * b_i w + c_i tanh(w / Omega_eps,i) with w = omega clamped to
 * [-Omega_max,i, Omega_max,i], so |f^| < u_s,max,i always. 0 when wa is NULL
 * or not initialised, i out of range or omega not finite. Total.
 */
real_t aocs_wheels_friction(const aocs_wheels_t *wa, uint32_t i, real_t omega_radps);

/* Wheel i's friction model replaced by (viscous_nms, coulomb_nm) (fault management's friction test, docs/spec.md
 * 5.15.2), checked as aocs_wheels_init checks it (AOCS_ERR_WHEEL_FRICTION_NEGATIVE, _EXCEEDS_LIMIT); nothing else
 * changes (the model enters neither Gs^+ nor the null projector). AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED
 * (also for i >= n); on an error wa is unchanged. */
aocs_status_t aocs_wheels_set_friction(aocs_wheels_t *wa, uint32_t i, real_t viscous_nms, real_t coulomb_nm);

/* sum Js_i g_i Omega_i (B, N m s): the wheels' momentum relative to the body, for the feedforward
 * (docs/spec.md 5.1); zero when wa is NULL or not initialised or a speed is not finite. Total. */
aocs_vec3_t aocs_wheels_h_B(const aocs_wheels_t *wa, const real_t *omega_radps);

#endif /* AOCS_WHEEL_ARRAY_H */
