/*
 * Multiplicative extended Kalman filter (MEKF) of the attitude and the gyro
 * bias from a rate gyro and a star tracker: docs/spec.md section 5.6
 * (Lefferts, Markley, Shuster 1982; Markley & Crassidis 2014, ch. 6-7).
 *
 * State: the reference attitude q_BN_hat (scalar last, Shuster product,
 * A(q) maps N to B, docs/conventions.md) and the bias estimate b_hat
 * (rad/s); the 6-state error x = [dth; db] (dth the rotation vector of the
 * error quaternion, q_BN = dq(dth) (x) q_BN_hat, components in B; db = b -
 * b_hat) with covariance P (6x6, rad^2, rad^2/s, rad^2/s^2). The error is
 * reset into q_BN_hat and b_hat after every update (spec 5.6.6).
 *
 * Use (fixed size, no dynamic memory; one aocs_mekf_t per filter):
 *   aocs_mekf_config_default(&cfg);  ...set the sensor figures...
 *   aocs_mekf_init(&f, &cfg);                 validates, waits for a star-tracker sample
 *   loop: aocs_mekf_step(&f, &in, &out);      propagate with the gyro to in.t_ns, update
 *                                             with in.st when in.st.valid
 *   aocs_mekf_reset(&f);                      back to waiting (mode change, re-acquisition)
 * aocs_mekf_propagate and aocs_mekf_update are the two halves of a step.
 *
 * Time is the sample time in ns of one monotonic clock (the executive's
 * t_sensor_ns): the gyro rate held over (t_prev, t_ns] (spec 5.6.2), the
 * star-tracker sample taken at t_meas_ns <= t_ns and applied against the
 * estimate at t_meas_ns (spec 5.6.8, history of AOCS_MEKF_HISTORY_LEN steps).
 */
#ifndef AOCS_ESTIMATION_MEKF_H
#define AOCS_ESTIMATION_MEKF_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/math3.h"
#include "aocs/attitude.h"

/* steps of gyro increments kept for delayed star-tracker samples (spec 5.6.8) */
#define AOCS_MEKF_HISTORY_LEN 32u

/* |w_meas_i| above this is no gyro reading (AOCS_ERR_MEKF_RATE_RANGE) */
#define AOCS_MEKF_RATE_MAX_RADPS AOCS_R(100.0)

/* max_gap_s above this is refused at init (AOCS_ERR_DT_INVALID) */
#define AOCS_MEKF_MAX_GAP_LIMIT_S AOCS_R(3600.0)

/* |(|q_SN| - 1)| above this: the sample is not a unit quaternion (AOCS_ERR_QUAT_NOT_UNIT), both precisions */
#define AOCS_MEKF_QUAT_UNIT_TOL AOCS_R(1.0e-4)

/* how the filter takes its first estimate after aocs_mekf_init (spec 5.6.10, mekf.init_mode) */
#define AOCS_MEKF_INIT_FIRST_ST 0u    /* from the first valid star-tracker sample (the default) */
#define AOCS_MEKF_INIT_CONFIGURED 1u  /* from the configured q0_BN at the first step with a gyro rate */
#define AOCS_MEKF_INIT_COUNT 2u

/* chi-square, 3 degrees of freedom, 99.9 % quantile: the default gate (spec 5.6.7) */
#define AOCS_MEKF_GATE_CHI2_3DOF_999 AOCS_R(16.266236196238129)

typedef struct {
    aocs_quat_t q_SB;            /* star-tracker mounting: A(q_SB) maps B to the tracker frame S */
    real_t st_sigma_cross_rad;   /* tracker noise 1-sigma about x and y of S (cross-boresight), rad, > 0 */
    real_t st_sigma_about_rad;   /* tracker noise 1-sigma about z of S (about the boresight), rad, > 0 */
    real_t gyro_arw_radpsqrts;   /* angle random walk sigma_v, rad/s^0.5, > 0 */
    real_t gyro_rrw_radps1p5;    /* rate random walk sigma_u, rad/s^1.5, > 0 */
    aocs_vec3_t bias0_B_radps;   /* bias prior at initialisation, rad/s, finite */
    real_t p0_att_sigma_rad;     /* initial attitude 1-sigma per axis, rad, > 0 */
    real_t p0_bias_sigma_radps;  /* initial bias 1-sigma per axis, rad/s, > 0 */
    real_t gate_chi2;            /* innovation gate on d^2 = y^T S^-1 y, > 0 (default 3 dof 99.9 %) */
    real_t max_gap_s;            /* longest propagation step accepted, s, > 0 (AOCS_ERR_MEKF_GAP beyond) */
    uint32_t init_mode;          /* AOCS_MEKF_INIT_FIRST_ST or AOCS_MEKF_INIT_CONFIGURED (< AOCS_MEKF_INIT_COUNT) */
    aocs_quat_t q0_BN;           /* AOCS_MEKF_INIT_CONFIGURED: the attitude estimate the filter starts from,
                                    unit within AOCS_MEKF_QUAT_UNIT_TOL (checked in both modes) */
    /* the gyroless model (spec 5.6.12), flown after fault management excludes the gyro */
    real_t gyroless_torque_sigma_nm;      /* unmodelled body torque, white, N m s^0.5 (1-sigma of its
                                             spectral density), >= 0; 0: no gyroless model */
    real_t gyroless_p0_rate_sigma_radps;  /* rate 1-sigma per axis at the switch, rad/s, > 0 */
    real_t gyroless_rate_sigma_radps;     /* the rate estimate is usable (AOCS_OK) once every rate
                                             1-sigma is at or below it, rad/s, > 0 */
} aocs_mekf_config_t;

/* A quaternion in double (scalar last): the reference attitude of both builds (spec 5.6.9). */
typedef struct {
    double q[4];
} aocs_mekf_quatd_t;

/* A 6x6 matrix, row-major m[row][col]; rows/cols 0..2 attitude error, 3..5 bias error. */
typedef struct {
    real_t m[6][6];
} aocs_mekf_mat6_t;

/* One star-tracker sample. */
typedef struct {
    aocs_quat_t q_SN;            /* attitude of the tracker frame S, unit within AOCS_MEKF_QUAT_UNIT_TOL */
    uint64_t t_meas_ns;          /* time of measurement, ns, <= the current time */
    uint32_t valid;              /* 0: no sample this step */
} aocs_mekf_st_sample_t;

/* The input of one step. */
typedef struct {
    uint64_t t_ns;               /* current time (gyro sample), ns, strictly increasing */
    aocs_vec3_t w_meas_B_radps;  /* measured body rate, rad/s, held over (t_prev, t_ns] */
    aocs_mekf_st_sample_t st;    /* star tracker, used when st.valid != 0 */
} aocs_mekf_input_t;

/* One entry of the gyro history (spec 5.6.8). */
typedef struct {
    uint64_t t0_ns;              /* start of the step */
    uint64_t t1_ns;              /* end of the step */
    aocs_quat_t dq;              /* the step's rotation: q_hat(t1) = dq (x) q_hat(t0) */
    aocs_vec3_t w_B_radps;       /* the rate it used, omega_m - b_hat (gyroless: the rate estimate) */
    aocs_vec3_t w_corr_B_radps;  /* gyroless: the filter's sum of rate corrections when it was made (5.6.12) */
} aocs_mekf_hist_t;

/* The estimate (zeroed, valid = 0, on any non-OK step). */
typedef struct {
    aocs_quat_t q_BN_hat;        /* attitude estimate, unit, q4 >= 0 */
    aocs_vec3_t w_BN_B_hat;      /* rate estimate omega_m - b_hat, rad/s */
    aocs_vec3_t bias_B_hat;      /* gyro bias estimate, rad/s */
    real_t sigma[6];             /* sqrt of diag P: attitude (rad) x y z, bias (rad/s) x y z */
    aocs_mekf_mat6_t P;          /* the full covariance */
    uint32_t valid;              /* 1: the estimate may be used */
    aocs_status_t st_status;     /* the star-tracker sample this step: AOCS_OK used, AOCS_ERR_INPUT_MISSING
                                    none offered, else why it was rejected */
    uint32_t n_updates;          /* samples used since the last init / reset */
    uint32_t n_gated;            /* samples rejected by the chi-square gate */
    uint32_t n_hostile;          /* samples rejected as malformed (NaN, non-unit, stale, future, too old) */
    uint32_t n_restarts;         /* times the filter went back to waiting (gap, covariance failure) */
    aocs_vec3_t innovation_B_rad;/* last innovation y formed (used or gated), B at the current time */
    real_t innovation_chi2;      /* its d^2 = y^T S^-1 y */
    aocs_vec3_t innovation_white;/* z = L^-1 y, S = L L^T (Cholesky): |z|^2 = d^2, N(0, I) under the model */
    uint64_t t_ns;               /* time of the estimate */
} aocs_mekf_output_t;

typedef struct {
    /* parameters (validated copy) */
    aocs_mekf_config_t cfg;
    real_t r_S[3];               /* tracker noise variances on the axes of S, rad^2 */
    real_t p_floor[6];           /* floor of diag P (spec 5.6.9) */
    /* internal state */
    aocs_mekf_quatd_t q_BN_hat;  /* the reference attitude, in double in both builds (spec 5.6.9) */
    aocs_vec3_t bias_B_hat;
    aocs_vec3_t w_meas_B_radps;  /* gyro rate of the last propagation (output rate: it minus b_hat) */
    aocs_mekf_mat6_t P;
    aocs_mekf_hist_t hist[AOCS_MEKF_HISTORY_LEN];
    uint32_t hist_count;         /* entries filled, <= AOCS_MEKF_HISTORY_LEN */
    uint32_t hist_head;          /* index of the newest entry */
    uint64_t t_ns;               /* time of the estimate */
    uint64_t t_last_meas_ns;     /* time of measurement of the last sample used */
    uint32_t started;            /* 1 once initialised from a star-tracker sample (or q0_BN) */
    uint32_t configured_start;   /* 1 from init until the first start when init_mode is AOCS_MEKF_INIT_CONFIGURED */
    uint32_t have_meas;          /* 1 once a sample was used (t_last_meas_ns meaningful) */
    uint32_t n_updates;
    uint32_t n_gated;
    uint32_t n_hostile;
    uint32_t n_restarts;
    aocs_vec3_t innovation_B_rad;
    real_t innovation_chi2;
    aocs_vec3_t innovation_white;
    real_t st_noise_scale;       /* the tracker's noise variances are cfg's times this (spec 5.15.3), >= 1;
                                    set by aocs_mekf_set_st_noise_scale, kept across reset and restart */
    uint32_t st_excluded;        /* 1: a sample is tested (innovation, gate) but not applied (spec 5.15.3);
                                    set by aocs_mekf_set_st_excluded, kept across reset and restart */
    /* the gyroless model (spec 5.6.12): set by aocs_mekf_set_gyroless, kept across reset and restart */
    uint32_t gyroless;           /* 1: propagate on the rigid-body dynamics; P's rows 3..5 are the rate error */
    aocs_mat3_t inertia_B_kgm2;  /* J */
    aocs_mat3_t inertia_inv_B;   /* J^-1 */
    aocs_vec3_t w_hat_B_radps;   /* the rate estimate (the state replacing the bias) */
    aocs_vec3_t w_corr_B_radps;  /* the sum of the updates' rate corrections (the history's rates are
                                    re-expressed with the corrections made after them, 5.6.12) */
    aocs_vec3_t tau_B_Nm;        /* body torque held over the next propagation (aocs_mekf_set_torque) */
    aocs_vec3_t h_wheels_B_Nms;  /* wheel momentum held over it */
    int initialised;             /* set by a successful init only */
} aocs_mekf_t;

/* Defaults: identity mounting, 1 / 8 arcsec tracker, ARW 1e-6 rad/s^0.5, RRW 1e-9 rad/s^1.5, zero bias
 * prior, P0 1 deg and 1 deg/h, gate AOCS_MEKF_GATE_CHI2_3DOF_999, max_gap_s 10, init_mode
 * AOCS_MEKF_INIT_FIRST_ST, q0_BN identity. Total (NULL: nothing). */
void aocs_mekf_config_default(aocs_mekf_config_t *cfg);

/*
 * Validates and copies cfg, then resets. First failure wins: AOCS_ERR_NULL_ARG;
 * a non-finite value -> AOCS_ERR_PARAM_NOT_FINITE; q_SB not unit within
 * AOCS_MEKF_QUAT_UNIT_TOL -> AOCS_ERR_QUAT_NOT_UNIT (also q0_BN); a sigma <= 0 ->
 * AOCS_ERR_MEKF_NOISE_NOT_POSITIVE; gate_chi2 <= 0 -> AOCS_ERR_MEKF_GATE_INVALID;
 * max_gap_s <= 0 or > AOCS_MEKF_MAX_GAP_LIMIT_S -> AOCS_ERR_DT_INVALID; init_mode >= AOCS_MEKF_INIT_COUNT
 * -> AOCS_ERR_MEKF_INIT_MODE_INVALID. Not initialised on failure. With AOCS_MEKF_INIT_CONFIGURED the
 * first step with a gyro rate starts the filter at q0_BN (spec 5.6.10); every later start (after a
 * restart or aocs_mekf_reset) is from a star-tracker sample.
 */
aocs_status_t aocs_mekf_init(aocs_mekf_t *f, const aocs_mekf_config_t *cfg);

/* Back to waiting for the first star-tracker sample (whatever init_mode); counters and history cleared. AOCS_ERR_NULL_ARG,
 * AOCS_ERR_NOT_INITIALISED. */
aocs_status_t aocs_mekf_reset(aocs_mekf_t *f);

/*
 * Propagation (spec 5.6.2-5.6.4) from the estimate's time to t_ns with the
 * rate held. AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED,
 * AOCS_ERR_MEKF_NO_ATTITUDE (not started), AOCS_ERR_INPUT_NOT_FINITE (rate),
 * AOCS_ERR_MEKF_RATE_RANGE (|w_i| > AOCS_MEKF_RATE_MAX_RADPS),
 * AOCS_ERR_INPUT_STALE (t_ns not after the estimate's time): state untouched;
 * AOCS_ERR_MEKF_GAP (step > max_gap_s) and AOCS_ERR_MEKF_COV_INVALID: the
 * filter goes back to waiting for a star-tracker sample.
 */
aocs_status_t aocs_mekf_propagate(aocs_mekf_t *f, aocs_vec3_t w_meas_B_radps, uint64_t t_ns);

/*
 * Update with one star-tracker sample (spec 5.6.5-5.6.8); returns its verdict:
 * AOCS_OK used; AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED,
 * AOCS_ERR_MEKF_NO_ATTITUDE; hostile (n_hostile counted, state untouched):
 * AOCS_ERR_INPUT_NOT_FINITE, AOCS_ERR_QUAT_NOT_UNIT, AOCS_ERR_MEKF_MEAS_FUTURE
 * (after the estimate's time), AOCS_ERR_INPUT_STALE (not after the last
 * sample used), AOCS_ERR_MEKF_MEAS_TOO_OLD (before the history);
 * AOCS_ERR_MEKF_GATED (n_gated counted, state untouched);
 * AOCS_ERR_MEKF_COV_INVALID (numerical failure: the filter goes back to waiting).
 */
aocs_status_t aocs_mekf_update(aocs_mekf_t *f, const aocs_mekf_st_sample_t *st);

/*
 * One step: when started, propagate to in->t_ns then update with in->st
 * when valid; when not started, initialise from in->st (spec 5.6.10) and
 * propagate from its t_meas_ns to in->t_ns, or (the first start of
 * AOCS_MEKF_INIT_CONFIGURED) start at q0_BN at in->t_ns and update with in->st when valid. Returns AOCS_OK when *out holds a
 * usable estimate (a rejected star-tracker sample does not make the step
 * fail: its verdict is out->st_status), else the error with *out zeroed
 * (out->st_status still the sample's verdict, counters still reported).
 */
aocs_status_t aocs_mekf_step(aocs_mekf_t *f, const aocs_mekf_input_t *in, aocs_mekf_output_t *out);

/* Fault management (spec 5.15.3, the noise adaptation): the star tracker's noise variances become the
 * configured ones times scale (its 1-sigma times sqrt(scale)) from the next update. A scale that is not finite
 * or below 1 is taken as 1. Kept across reset and restart, not across init. No-op on NULL or before init. */
void aocs_mekf_set_st_noise_scale(aocs_mekf_t *f, real_t scale);

/* Fault management (spec 5.15.3): excluded != 0 refuses every star-tracker sample after its innovation test
 * (aocs_mekf_update returns AOCS_ERR_MEKF_ST_EXCLUDED, state untouched, d^2 kept); 0 uses them again. A
 * filter not yet started still starts from a tracker sample. No-op on NULL. */
void aocs_mekf_set_st_excluded(aocs_mekf_t *f, uint32_t excluded);

/*
 * Fault management (spec 5.6.12, 5.15.4): the gyro is excluded; from the next step the filter propagates on
 * the rigid-body dynamics J dw/dt = tau - w x (J w + h_w) with the torque and wheel momentum of
 * aocs_mekf_set_torque, its state the attitude and the rate (the bias estimate is kept, unused), and takes the
 * tracker as before. At the switch the rate estimate is w_hat (the last one the gyro gave, or zero), its
 * covariance gyroless_p0_rate_sigma^2 I, the attitude's p0_att_sigma^2 I (the gyro may have spoiled it), no
 * cross terms. AOCS_OK; AOCS_ERR_NULL_ARG; AOCS_ERR_NOT_INITIALISED; AOCS_ERR_MEKF_NOISE_NOT_POSITIVE when
 * gyroless_torque_sigma_nm is 0 (no model configured); the inertia codes of aocs_mat3_check_inertia
 * (nothing changed on an error). Once gyroless the filter stays so (until init).
 */
aocs_status_t aocs_mekf_set_gyroless(aocs_mekf_t *f, const aocs_mat3_t *inertia_B_kgm2, aocs_vec3_t w_hat_B_radps);

/* The body torque (N m, B) the actuators apply from now to the next step and the wheels' momentum (N m s, B),
 * for the gyroless propagation; ignored (kept) while the filter uses its gyro. A non-finite vector is taken as
 * zero. No-op on NULL. */
void aocs_mekf_set_torque(aocs_mekf_t *f, aocs_vec3_t tau_B_Nm, aocs_vec3_t h_wheels_B_Nms);

/* 1 when the filter propagates on the dynamics (aocs_mekf_set_gyroless succeeded), else 0. Total. */
uint32_t aocs_mekf_is_gyroless(const aocs_mekf_t *f);

/* Fault management (docs/spec.md 5.15.4): after a detected jump of the gyro's bias, the bias block of P back to
 * its prior p0_bias_sigma^2 I and the attitude-bias cross covariance to zero (P stays symmetric positive
 * definite: two positive definite diagonal blocks); the estimates are kept. The filter then re-estimates the
 * bias as fast as at its start. No-op on NULL, before init, while the filter waits for its first sample, and
 * once gyroless (no bias state). */
void aocs_mekf_reinflate_bias(aocs_mekf_t *f);

/* The current estimate into *out (st_status AOCS_ERR_INPUT_MISSING). AOCS_OK, or the reason with *out zeroed:
 * AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED, AOCS_ERR_MEKF_NO_ATTITUDE. */
aocs_status_t aocs_mekf_get_output(const aocs_mekf_t *f, aocs_mekf_output_t *out);

#endif /* AOCS_ESTIMATION_MEKF_H */
