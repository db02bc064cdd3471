/*
 * The fault-management stage (issue 26; docs/spec.md 5.15): the last stage of
 * the executive's step (after actuation and momentum management). It tests
 * residuals against stated thresholds with persistence counters (Isermann
 * 2006, ch. 7 and 10: residual generation, threshold with persistence),
 * raises the events of aocs/fdir/events.def into its log, and decides the
 * isolation and recovery actions the executive applies:
 *
 *   wheel residual   (wheel_monitor.c) r_i = [u_s,i - f^_i(Omega_i)](k-1) - Js_i (Omega_i(k) - Omega_i(k-1)) / T:
 *                    |r_i| > frac u_s,max,i on N consecutive steps -> wheel_residual_high, wheel_isolated
 *                    (the array re-initialised without wheel i, the slew replanned), or, when the wheels
 *                    left would not span three axes, wheel_isolation_refused and SAFE latched;
 *                    over fdir.wheel_friction_window steps sum r_i / sum f^_i - 1 > fdir.wheel_friction_excess
 *                    -> wheel_friction_high, the wheel's friction model scaled by that ratio;
 *   star tracker     (st_monitor.c) the MEKF innovation d^2 = y^T S^-1 y > chi2 on N samples ->
 *                    st_innovation_high, st_excluded (tested, not applied); M consistent samples ->
 *                    st_restored; excluded so, a window of fdir.st_restore samples whose whitened innovation
 *                    is white with zero mean but m times its model's spread -> st_noise_rescaled, the tracker
 *                    re-admitted with its noise variances times m (and followed while rescaled);
 *                    K identical quaternions while the gyro turns -> st_frozen, st_excluded;
 *   gyro             (gyro_monitor.c) a component at the saturation limit on K samples, or stuck
 *                    (bit-identical on K samples while another component changed) -> gyro_saturated /
 *                    gyro_stuck, then gyro_excluded and, when the estimator can go on without it,
 *                    estimator_gyroless (the MEKF propagates on the dynamics, 5.6.12; SAFE until its rate
 *                    is known, then NOMINAL), else SAFE latched (one gyro: nothing to propagate on);
 *   momentum         (momentum_monitor.c) over windows of M periods, the change of the total angular
 *                    momentum H_N = A(q)^T (J w + h_wheels) minus the impulse the thrusters were commanded to
 *                    give: above fdir.mom_residual_nm on P windows in a row and explained by one commanded
 *                    thruster that did not fire -> thruster_ineffective, unload_actuator_switched (the
 *                    allocation recomputed without it); not explained -> momentum_inconsistent;
 *   stuck open       (latch_isolation.c) a period's momentum residual that is one thruster's whole-period
 *                    impulse on fdir.thr_open_persist periods in a row -> thruster_stuck_open and the latch
 *                    valve of its branch closed (thruster_branch_closed; reopened and the other one closed
 *                    when the residual goes on: thruster_branch_reopened); the next consistent window ->
 *                    thruster_isolated;
 *   modes and link   (fdir.c) safe_entered / safe_left (after the first NOMINAL step), link_lost /
 *                    link_restored from consecutive missing samples.
 *
 * Fixed size, no dynamic memory, total on any input. Disabled (fdir.enabled = 0) it raises nothing and
 * decides nothing; enabled it is silent on a nominal run (the thresholds, docs/spec.md 5.15).
 */
#ifndef AOCS_FDIR_FDIR_H
#define AOCS_FDIR_FDIR_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/math3.h"
#include "aocs/attitude.h"
#include "aocs/actuation/wheel_array.h"
#include "aocs/estimation/estimate.h"
#include "aocs/exec/modes.h"
#include "aocs/fdir/event_log.h"
#include "aocs/momentum/momentum.h"

/* Defaults (docs/spec.md 5.15, where each is argued) */
#define AOCS_FDIR_WHEEL_RESIDUAL_FRAC_DEFAULT AOCS_R(0.1)
#define AOCS_FDIR_WHEEL_PERSIST_DEFAULT 5u
#define AOCS_FDIR_ST_CHI2_DEFAULT AOCS_R(16.266236196238129) /* chi-square 3 dof, 99.9 % */
#define AOCS_FDIR_ST_PERSIST_DEFAULT 5u
#define AOCS_FDIR_ST_RESTORE_DEFAULT 20u
#define AOCS_FDIR_ST_FROZEN_SAMPLES_DEFAULT 5u
#define AOCS_FDIR_ST_FROZEN_RATE_DEFAULT AOCS_R(1.0e-4)
#define AOCS_FDIR_GYRO_STUCK_SAMPLES_DEFAULT 10u
#define AOCS_FDIR_GYRO_SAT_DEFAULT AOCS_R(0.0)
/* a gyro every axis of which repeats while the tracker turns faster than it says by this many times
 * fdir.st_frozen_rate_radps (1e-3 rad/s by default: over 0.9 s some 190 arcsec, far beyond a tracker's noise
 * between two samples) is pinned: saturated or stuck (5.15.4) */
#define AOCS_FDIR_GYRO_PINNED_RATE_FACTOR AOCS_R(10.0)
#define AOCS_FDIR_GYRO_BIAS_CHI2_DEFAULT AOCS_R(25.0) /* 1 dof per axis: 5 sigma */
#define AOCS_FDIR_GYRO_BIAS_PERSIST_DEFAULT 10u
#define AOCS_FDIR_LINK_LOST_PERIODS_DEFAULT 3u
#define AOCS_FDIR_MOM_RESIDUAL_DEFAULT AOCS_R(0.0) /* off: the external torque bound is the mission's */
#define AOCS_FDIR_MOM_WINDOW_DEFAULT 30u
#define AOCS_FDIR_MOM_PERSIST_DEFAULT 2u
#define AOCS_FDIR_THR_OPEN_PERSIST_DEFAULT 3u
#define AOCS_FDIR_WHEEL_FRICTION_WINDOW_DEFAULT 100u
#define AOCS_FDIR_WHEEL_FRICTION_EXCESS_DEFAULT AOCS_R(1.0) /* the friction doubled */
/* the star tracker's noise adaptation (5.15.3): its noise variances at most this many times the configured
 * ones (1e4: its 1-sigma 100 times); 0 = no adaptation */
#define AOCS_FDIR_ST_NOISE_SCALE_MAX_DEFAULT AOCS_R(1.0e4)
/* the adaptation's whiteness test: W |z_mean|^2 / m, chi-square with 3 degrees of freedom at 99.9 % */
#define AOCS_FDIR_ST_MEAN_CHI2 AOCS_R(16.266236196238129)
/* a rescaled tracker's spread m followed when outside [LO, HI]: a window of W = 20 samples estimates m with
 * some 20 % of scatter (chi-square of 3 (W - 1) degrees of freedom), and its innovations, against a model
 * that was itself estimated, are not exactly white: at [1/2, 2] the scale was seen to chatter (5.15.3) */
#define AOCS_FDIR_ST_NOISE_BAND_LO AOCS_R(0.25)
#define AOCS_FDIR_ST_NOISE_BAND_HI AOCS_R(4.0)

typedef struct {
    uint32_t enabled;             /* fdir.enabled: 1 on (default), 0 off */
    real_t wheel_residual_frac;   /* wheel residual threshold as a fraction of u_s,max,i, (0, 1] */
    uint32_t wheel_persist;       /* consecutive steps above it, >= 1 */
    real_t st_chi2;               /* innovation chi-square threshold, > 0 */
    uint32_t st_persist;          /* consecutive tracker samples above it to exclude, >= 1 */
    uint32_t st_restore;          /* consecutive samples at or below it to restore, >= 1 */
    uint32_t st_frozen_samples;   /* identical tracker quaternions (while turning) for st_frozen, >= 2 */
    real_t st_frozen_rate_radps;  /* |gyro| above which the tracker must change, rad/s, > 0 */
    uint32_t gyro_stuck_samples;  /* identical gyro component while the tracker turns, >= 2 */
    real_t gyro_sat_radps;        /* |gyro component| at which it is saturated, rad/s; 0 = no test */
    real_t gyro_bias_chi2;        /* bias-jump test threshold, 1 dof per axis; 0 = no test */
    uint32_t gyro_bias_persist;   /* consecutive tracker samples above it that make a bias jump, >= 1 */
    uint32_t link_lost_periods;   /* consecutive missing samples for link_lost, >= 1 */
    real_t mom_residual_nm;       /* momentum test: mean unexplained external torque over a window, N m; 0 = none */
    uint32_t mom_window;          /* control periods per momentum window, >= 1 */
    uint32_t mom_persist;         /* consecutive inconsistent windows for an event, >= 1 */
    uint32_t thr_open_persist;    /* consecutive periods matching a stuck-open thruster to close its branch, >= 1 */
    uint32_t wheel_friction_window; /* steps of the friction test's sums, >= 1 */
    real_t wheel_friction_excess; /* friction beyond the model by this fraction of it: high; 0 = no test */
    real_t st_noise_scale_max;    /* the tracker's noise variances at most this times the model's; 0 = no
                                     noise adaptation (5.15.3) */
} aocs_fdir_config_t;

/* What the stage sees of one step (the executive fills it after actuation). */
typedef struct {
    uint64_t t_ns;                /* sensor time of the step (the last sample's on a step without one) */
    real_t period_s;              /* control period T, s */
    int have_sample;              /* 0: a period without a sample (step_no_input) */
    uint32_t missing;             /* samples missed before this one (tick gap), counted by the acceptance */
    aocs_status_t input_status;   /* the acceptance's verdict on the sample */
    aocs_exec_mode_t mode;        /* the mode flown this step */
    /* the sample's sensors (read only when have_sample and input_status is AOCS_OK) */
    const real_t *wheel_speed_radps; /* tachometers, AOCS_WHEELS_MAX entries (NULL: none) */
    aocs_vec3_t gyro_w_B;         /* gyro rate, rad/s */
    int gyro_valid;
    aocs_quat_t st_q_SN;          /* star-tracker quaternion of this sample */
    int st_valid;                 /* a new tracker sample this step */
    const aocs_det_output_t *est; /* the determination stage's output (st_status, innovation_chi2) */
    real_t gyro_rrw_radps1p5;     /* the filter's gyro rate random walk sigma_u, rad/s^1.5 (0: no filter) */
    int gyroless_capable;         /* 1: the estimator can go on without the gyro (docs/spec.md 5.6.12) */
    const aocs_wheels_alloc_t *alloc; /* this step's wheel allocation (NULL without an array) */
    aocs_status_t wheels_status;  /* the allocation's status this step */
    aocs_mom_t *mom;              /* the momentum stage after this step (its thruster commands; NULL: none);
                                   * a thruster isolation recomputes its allocation in place */
} aocs_fdir_input_t;

/* The wheel monitor's state (wheel_monitor.c) */
typedef struct {
    real_t u_net_prev_nm[AOCS_WHEELS_MAX];  /* u_s - f^(Omega) commanded last step, N m */
    real_t omega_prev_radps[AOCS_WHEELS_MAX];
    uint32_t over[AOCS_WHEELS_MAX];        /* consecutive steps above the threshold */
    int have_prev;
    /* the friction test: sums over the window of the residual and of the friction model, N m */
    real_t f_prev_nm[AOCS_WHEELS_MAX];     /* the friction model at last step's speed */
    real_t sum_r_nm[AOCS_WHEELS_MAX];
    real_t sum_f_nm[AOCS_WHEELS_MAX];
    real_t sum_abs_f_nm[AOCS_WHEELS_MAX];
    uint32_t friction_steps;               /* steps summed so far */
    uint32_t friction_high_mask;           /* bit i: wheel i's friction found high (its model now follows it) */
    uint32_t friction_tainted_mask;        /* bit i: a residual above the isolation threshold in this window */
} aocs_fdir_wheels_t;

/* The star-tracker monitor's state (st_monitor.c) */
typedef struct {
    uint32_t high_run;            /* consecutive samples above st_chi2 */
    uint32_t good_run;            /* while excluded: consecutive samples at or below it */
    uint32_t frozen_run;          /* consecutive identical quaternions while turning */
    aocs_quat_t q_prev_SN;
    int have_prev;
    int excluded;                 /* 1: the MEKF refuses the tracker (applied by the executive) */
    int excluded_by_innovation;   /* 1: excluded by the innovation test (not frozen) */
    /* the noise adaptation (5.15.3): windows of fdir.st_restore tested samples of the whitened innovation */
    real_t noise_scale;           /* the tracker's noise variances are the model's times this, >= 1 */
    uint32_t win_n;               /* samples in the window so far */
    aocs_vec3_t win_sum_z;        /* their sum */
    real_t win_sum_zz;            /* the sum of their |z|^2 */
} aocs_fdir_st_t;

/* The gyro monitor's state (gyro_monitor.c) */
typedef struct {
    aocs_vec3_t w_prev_B;
    uint32_t stuck_run[3];
    uint32_t sat_run[3];
    int have_prev;
    int excluded;
    /* the pinned test: every axis repeating while the tracker turns (gyro_monitor.c) */
    uint32_t pinned_run;          /* consecutive samples with every axis identical to the last */
    aocs_quat_t st_ref_SN;        /* the tracker's sample when the run began */
    int have_st_ref;
    real_t pinned_angle_rad;      /* the rotation the gyro reports over the run, sum |w| T */
    real_t pinned_span_s;         /* the run's length */
    aocs_quat_t st_last_SN;       /* the last tracker sample (any step) */
    int have_st_last;
    /* the bias-jump test (gyro_bias.c): the filter's bias estimate and its variances at the reference time */
    aocs_vec3_t b_ref_B;          /* bias estimate at t_ref, rad/s */
    real_t p_ref[3];              /* its variances (diag of the bias block of P), rad^2/s^2 */
    uint64_t t_ref_ns;
    uint32_t restarts_ref;        /* the filter's restart count at t_ref (a restart re-arms) */
    uint32_t bias_run;            /* consecutive tested samples above gyro_bias_chi2 */
    int bias_armed;
} aocs_fdir_gyro_t;

/* The momentum monitor's state (momentum_monitor.c): the window open since H_ref was measured */
typedef struct {
    aocs_vec3_t h_ref_N;          /* total momentum at the window's start, N, N m s */
    real_t epoch_ref_Nms;         /* its epoch uncertainty, |h_w(k) - h_w(k-1)| / 2, N m s */
    aocs_vec3_t hw_prev_B;        /* the wheels' momentum at the last usable sample, B, N m s */
    int have_hw_prev;
    aocs_vec3_t expected_N;       /* thruster impulse commanded since, N, N m s */
    aocs_vec3_t thr_impulse_N[AOCS_MOM_THRUSTERS_MAX]; /* each thruster's share of it, N m s */
    uint32_t periods;             /* periods in the window so far */
    int open;                     /* 1: h_ref_N holds a window's start */
    uint32_t inconsistent_run;    /* consecutive windows not explained by any thruster */
    uint32_t ineffective_run;     /* consecutive windows explained by one commanded thruster not firing */
    uint32_t suspect;             /* that thruster (the last window's) */
    /* the last period, for the stuck-open test (latch_isolation.c) */
    aocs_vec3_t h_prev_N;         /* total momentum at the last usable sample, N, N m s */
    real_t epoch_prev_Nms;        /* its epoch uncertainty, N m s */
    aocs_mat3_t a_prev_NB;        /* A(q)^T at it */
    aocs_vec3_t c_prev_N;         /* the impulse the thrusters were commanded over the period since, N, N m s */
    real_t on_prev_s[AOCS_MOM_THRUSTERS_MAX]; /* their on-times over it, s */
    int have_period;              /* 1: the fields above hold the last sample's */
    /* the stuck-open test and its isolation by the latch valves (latch_isolation.c) */
    uint32_t open_run;            /* consecutive periods whose residual is one thruster's whole-period impulse */
    uint32_t open_suspect;        /* that thruster */
    uint32_t latch_testing;       /* 1 + the branch whose valve is closed to test; 0: no test under way */
    uint32_t latch_tried;         /* bit b: branch b closed to test (a branch is tested once) */
    uint32_t latch_suspect;       /* the thruster the test under way isolates */
} aocs_fdir_mom_t;

typedef struct {
    aocs_fdir_config_t cfg;
    aocs_evlog_t log;
    aocs_fdir_wheels_t wheels;
    aocs_fdir_st_t st;
    aocs_fdir_gyro_t gyro;
    aocs_fdir_mom_t mom;
    uint32_t missing_run;         /* consecutive periods without a sample */
    uint32_t link_down;           /* 1 after link_lost until a sample */
    aocs_exec_mode_t mode_prev;
    int flown_nominal;            /* 1 once a step flew NOMINAL */
    int safe_latched;             /* 1: an isolation was refused, or the gyro excluded with no gyroless
                                     estimator: stay in SAFE */
    int replan;                   /* 1: the wheels changed this step, the slew guidance must adapt */
    int reinflate_bias;           /* 1: a gyro bias jump this step: the filter's bias covariance back to its prior */
    int st_rescaled;              /* 1: st.noise_scale changed this step: the executive applies it to the filter */
    int go_gyroless;              /* 1: the gyro was excluded this step and the estimator can fly without it:
                                     the executive switches it to its gyroless model (5.6.12) */
    aocs_wheels_t wheels_before;  /* the array before the last isolation (the guidance's old envelope) */
    int initialised;
} aocs_fdir_t;

/* Defaults above, enabled. Total (no-op on NULL). */
void aocs_fdir_config_default(aocs_fdir_config_t *cfg);

/* AOCS_OK, AOCS_ERR_NULL_ARG, or AOCS_ERR_FDIR_CONFIG_INVALID (enabled not 0 or 1; enabled, a value out of
 * its range above). Disabled, the other values are not checked (a zeroed configuration is valid, off). */
aocs_status_t aocs_fdir_config_check(const aocs_fdir_config_t *cfg);

/* Checks and copies cfg, empty log, nothing excluded. On error f is not initialised. */
aocs_status_t aocs_fdir_init(aocs_fdir_t *f, const aocs_fdir_config_t *cfg);

/*
 * One step: the monitors, the events, the decisions. wheels: the executive's array (NULL without one);
 * an isolation re-initialises it without the wheel (aocs_wheels_init with the failed bit set) and sets
 * f->replan. After the call f->st.excluded is the tracker's state for the next step and f->safe_latched
 * holds the executive in SAFE. Disabled or not initialised: nothing. Total.
 */
void aocs_fdir_step(aocs_fdir_t *f, const aocs_fdir_input_t *in, aocs_wheels_t *wheels);

/* ---- the monitors (one per file), called by aocs_fdir_step with f enabled and initialised ---- */
void aocs_fdir_wheels_step(aocs_fdir_t *f, const aocs_fdir_input_t *in, aocs_wheels_t *wheels);
void aocs_fdir_st_step(aocs_fdir_t *f, const aocs_fdir_input_t *in);
void aocs_fdir_gyro_step(aocs_fdir_t *f, const aocs_fdir_input_t *in);
void aocs_fdir_gyro_bias_step(aocs_fdir_t *f, const aocs_fdir_input_t *in);
void aocs_fdir_mom_step(aocs_fdir_t *f, const aocs_fdir_input_t *in, const aocs_wheels_t *wheels);

/* The stuck-open test of the last period (latch_isolation.c; docs/spec.md 5.15.8): dr its momentum residual,
 * H_N(t_k) - H_N(t_k-1) - the commanded impulse, N m s, N, and bound its bound; closes, reopens and swaps latch
 * branches. 1 when it moved a valve (the caller then starts a new window). */
int aocs_fdir_open_test(aocs_fdir_t *f, const aocs_fdir_input_t *in, aocs_vec3_t dr_N, real_t bound);

/* A momentum window judged consistent (|r| <= bound): a latch test under way is confirmed (thruster_isolated). */
void aocs_fdir_latch_confirm(aocs_fdir_t *f, const aocs_fdir_input_t *in);

/* 1 when a and b are the same number (neither below nor above the other; 0 with a NaN): the repeat tests of
 * a frozen tracker and a stuck gyro axis. Total. */
int aocs_fdir_same(real_t a, real_t b);

/* n + 1, held at UINT32_MAX: the run counters of the monitors. Total. */
uint32_t aocs_fdir_count_up(uint32_t n);

/* The wheel residual r_i of one wheel (N m, docs/spec.md 5.15.2): u_net_prev - Js (omega - omega_prev) / T. */
real_t aocs_fdir_wheel_residual(real_t u_net_prev_nm, real_t js_kgm2, real_t omega_prev_radps, real_t omega_radps,
                                real_t period_s);

#endif /* AOCS_FDIR_FDIR_H */
