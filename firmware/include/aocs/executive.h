/*
 * Fixed-rate executive: owns one control period (ARCHITECTURE.md "data
 * path"): check the inputs, pick the mode, run the selected law, saturate,
 * time the step against its budget, report counters.
 *
 *   aocs_exec_config_default(&cfg);        fill defaults, then set the law,
 *   cfg.law = AOCS_LAW_QUAT_PD;            its config, limits, period
 *   cfg.laws.quat_pd = ...;
 *   aocs_exec_init(&exec, &cfg);           validates everything
 *   loop: aocs_exec_step(&exec, &in, &out) (lockstep: one call per sensor sample)
 *   aocs_exec_select(&exec, law, &target)  run-time command (SIL command message)
 *
 * Real-time mode adds the period timer (absolute deadlines, no drift):
 *   aocs_exec_timer_init(&tmr, period_ns, first_deadline_ns);
 *   loop: aocs_hal_sleep_until_ns(deadline);
 *         aocs_exec_timer_period_start(&tmr, aocs_hal_time_ns(), &deadline);
 *         aocs_exec_step(...) or aocs_exec_step_no_input(...) when no sample came.
 *
 * Modes: STANDBY (zero command), NOMINAL (selected law), SAFE (attitude:
 * u = -k_safe w within the limits; orbit: zero force). The executive enters
 * SAFE on an invalid, stale or missing input or a law error, and returns to
 * the requested mode after recover_good_samples consecutive good samples
 * (a good sample: valid, fresh, no gap, and the law evaluates without error;
 * in SAFE the law is evaluated in the shadow to know that).
 *
 * The saturated command never exceeds the limits, whatever happens: NaN or
 * Inf from anywhere gives a zero command.
 *
 * Guidance (guidance.c): a target frame D that rotates at the constant rate
 * target_rotation_rate_D (rad/s, in D) relative to N. At each step, from the
 * sensor time t (exact closed form, no accumulated drift):
 *     qd(t) = dq(w (t - t0)) (x) qd0,  dq(theta) = [sin(|theta|/2) theta/|theta|; cos(|theta|/2)]
 * (the solution of qd' = 0.5 Xi(qd) w, the plant's Plant.target(t)), and
 *     wd_B = A(qe) w,            qe = q (x) qd^-1  (D's rate in B: we = w - wd_B)
 *     wd_dot_B = wd_B x w_BN_B   (d/dt of the B components, see guidance.c)
 * qd0 is the configured target, t0 = target_t0_ns (lockstep: sim time 0);
 * a new target from aocs_exec_select becomes qd0 at the time of the last
 * sample. A zero rate leaves the target exactly as given (bit for bit).
 *
 * Reaction wheels (wheels.c, wheel_array.h): with cfg.wheels.n != 0 the
 * saturated body torque is allocated to the wheels every step (minimum norm,
 * one uniform scale, speed protection from the tachometer speeds of the
 * sample); u_cmd is then the body torque the wheels deliver (the same
 * direction) and out.wheels holds the wheel torque commands, out.momentum the
 * total momentum and the speed margin. The motor commands include the
 * friction feedforward and the null-space wheel speed management of the
 * array's configuration (docs/spec.md 5.3.2) in NOMINAL and SAFE; STANDBY
 * commands no motor torque at all. Non-finite tachometer speeds give a
 * zero wheel command (wheels_status says why). Without an array nothing
 * changes.
 *
 * Gain tables (gain_tables.c): the designs compiled into gains/aocs_gains.h
 * by name or id, so a config can say "<design name>" instead of 18 numbers;
 * `aocs gains` registers them in gains/gain_tables.def.
 *
 * The laws themselves, their configs, states, budgets and config fields are
 * rows of aocs/laws.def (the law registry); everything here that lists laws
 * is expanded from it.
 */
#ifndef AOCS_EXECUTIVE_H
#define AOCS_EXECUTIVE_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/math3.h"
#include "aocs/attitude.h"
#include "aocs/actuation/wheel_array.h"
#include "aocs/laws.def"
#include "aocs/guidance/slew.h"
#include "gains/gain_tables.def"

/*
 * ---- law identifiers (laws.def, law_table.c) ----
 * AOCS_LAW_NONE = 0, then one id per AOCS_LAW_ROWS row in row order (the
 * wire values: crp_linear = 1 .. orbit_lqr = 10), then AOCS_LAW_COUNT.
 */
#define AOCS_LAW_ENUM_ROW(ID, ...) AOCS_LAW_##ID,
typedef enum {
    AOCS_LAW_NONE = 0, /* no law: STANDBY */
    AOCS_LAW_ROWS(AOCS_LAW_ENUM_ROW)
    AOCS_LAW_COUNT
} aocs_law_id_t;

/* CLI name of a law ("quat_pd"); "none" for AOCS_LAW_NONE, "unknown" when out of range. Total. */
const char *aocs_law_name(aocs_law_id_t law);

/*
 * Law id from its CLI name (exact, case-sensitive; "none" gives
 * AOCS_LAW_NONE). AOCS_ERR_UNKNOWN_LAW (and *law untouched) for any other
 * string, AOCS_ERR_NULL_ARG for NULL pointers.
 */
aocs_status_t aocs_law_from_name(const char *name, aocs_law_id_t *law);

/* 1 for a law whose formula includes the slew feedforward (AOCS_LAW_FEEDFORWARD_IN_FORMULA of laws.def:
 * the executive adds none to it), 0 otherwise. Total. */
int aocs_law_has_feedforward(aocs_law_id_t law);

/* 1 for an ORBIT law of laws.def (input pos/vel, output force), 0 otherwise. Total. */
int aocs_law_is_orbit(aocs_law_id_t law);

/* Declared host budget of one step of the law, ns (BUDGET_NS of its laws.def row); AOCS_EXEC_SAFE_BUDGET_NS
 * for AOCS_LAW_NONE and out of range. Total. */
uint64_t aocs_law_budget_ns(aocs_law_id_t law);

/* ---- modes ---- */
typedef enum {
    AOCS_EXEC_MODE_STANDBY = 0, /* zero command */
    AOCS_EXEC_MODE_NOMINAL,     /* selected law */
    AOCS_EXEC_MODE_SAFE,        /* rate damping (attitude) / zero force (orbit) */
    AOCS_EXEC_MODE_COUNT
} aocs_exec_mode_t;

/* "standby", "nominal", "safe"; "unknown" when out of range. Total. */
const char *aocs_exec_mode_name(aocs_exec_mode_t mode);

/* Where time comes from (ARCHITECTURE.md): the sensor message (lockstep) or the HAL clock. */
typedef enum {
    AOCS_EXEC_CLOCK_LOCKSTEP = 0, /* the sensor sample is the tick; HAL clock only times the step */
    AOCS_EXEC_CLOCK_REALTIME      /* sample age is also checked against aocs_hal_time_ns() */
} aocs_exec_clock_t;

/* Validity flags of aocs_exec_input_t.valid (set by the sensor adapter). */
#define AOCS_EXEC_VALID_ATT   (1u << 0) /* q_BN usable */
#define AOCS_EXEC_VALID_RATE  (1u << 1) /* w_BN_B usable */
#define AOCS_EXEC_VALID_ORBIT (1u << 2) /* pos_m, vel_mps usable */

/* Target held by the executive (attitude laws; the orbit law regulates to zero). */
typedef struct {
    aocs_quat_t qd_DN;      /* target attitude, unit */
    aocs_vec3_t wd_B;       /* target rate, rad/s */
    aocs_vec3_t wd_dot_B;   /* target angular acceleration, rad/s^2 */
} aocs_exec_target_t;

/*
 * ---- compiled gain tables (gains/gain_tables.def, gain_tables.c) ----
 * One id per row of the registration that `aocs gains` writes next to the
 * tables (design order of tools/gains.toml), then AOCS_GAIN_TABLE_COUNT.
 */
#define AOCS_GAIN_TABLE_ENUM_ROW(ID, ...) AOCS_GAIN_TABLE_##ID,
typedef enum {
    AOCS_GAIN_TABLE_ROWS(AOCS_GAIN_TABLE_ENUM_ROW)
    AOCS_GAIN_TABLE_COUNT
} aocs_gain_table_id_t;

/* Design name of a table (its tools/gains.toml section); "unknown" when out of range. Total. */
const char *aocs_gain_table_name(aocs_gain_table_id_t table);

/* The law a table was designed for (LQR_QUAT, HINF or ORBIT_LQR); AOCS_LAW_NONE when out of range. Total. */
aocs_law_id_t aocs_gain_table_law(aocs_gain_table_id_t table);

/*
 * Table id from its design name (exact, case-sensitive).
 * AOCS_ERR_GAIN_TABLE_UNKNOWN (and *table untouched) for any other string,
 * AOCS_ERR_NULL_ARG for NULL pointers.
 */
aocs_status_t aocs_gain_table_find(const char *name, aocs_gain_table_id_t *table);

/*
 * One config of each law (member CFG of every CFG_OWN row of laws.def); only
 * the one selected (at init or by select) must be valid. The variants of a
 * law share one config; the law id forces the variant (VARIANT column).
 */
#define AOCS_LAW_CFG_DECL_CFG_OWN(CFG_T, CFG) CFG_T CFG;
#define AOCS_LAW_CFG_DECL_CFG_SHARED(CFG_T, CFG)
#define AOCS_LAW_CONFIG_MEMBER(ID, NAME, INPUT, TITLE, STATE, STATE_T, CFG, CFG_T, CFG_USE, ...) \
    AOCS_LAW_CFG_DECL_##CFG_USE(CFG_T, CFG)
typedef struct {
    AOCS_LAW_ROWS(AOCS_LAW_CONFIG_MEMBER)
} aocs_exec_law_configs_t;

/*
 * Copies the 3x6 gain of `table` into the config of `law` in *cfgs: the
 * MEMBER of the law's TABLE field in laws.def (lqr_quat.k, hinf.k,
 * orbit_lqr.k); nothing else changes.
 * AOCS_ERR_NULL_ARG; AOCS_ERR_GAIN_TABLE_UNKNOWN (table out of range);
 * AOCS_ERR_GAIN_TABLE_WRONG_LAW (the table was designed for another law,
 * *cfgs untouched). The law's init still validates the gain.
 */
aocs_status_t aocs_gain_table_apply(aocs_gain_table_id_t table, aocs_law_id_t law,
                                    aocs_exec_law_configs_t *cfgs);

/*
 * ---- Slew guidance (aocs/guidance/slew.h, docs/spec.md "Slew guidance") ----
 * STEP: the law sees the commanded target at once (the reference papers' runs,
 * bit for bit). SLEW: a commanded target (the init target, or a new one from
 * aocs_exec_select) starts a rest-to-rest eigenaxis slew from the attitude of
 * the next good sample; the attitude laws track qd(t), wd_B(t), wd_dot_B(t)
 * (the profile's D-frame rates rotated into B by A(qe), wd_dot_B the
 * derivative of those B components, as for the rotating target), and the
 * executive adds u_ff = J wd_dot_B + wd_B x (J wd_B + h_wheels) (h_wheels = 0:
 * no wheel array yet) to the output of every law not listed in
 * AOCS_LAW_FEEDFORWARD_IN_FORMULA (laws.def), then saturates. The envelope
 * is the executive's limits (u_max_axis, u_max_norm). A slew needs a fixed
 * target (no target_rotation_rate, zero wd/wd_dot). Orbit laws ignore it.
 */
typedef enum {
    AOCS_GUIDANCE_MODE_STEP = 0,
    AOCS_GUIDANCE_MODE_SLEW,
    AOCS_GUIDANCE_MODE_COUNT
} aocs_guidance_mode_t;

typedef struct {
    aocs_guidance_mode_t mode;    /* default STEP */
    aocs_slew_config_t slew;      /* checked in SLEW mode only; inertia = the plant's (fsw_node: key inertia) */
} aocs_exec_guidance_config_t;

typedef struct {
    real_t period_s;              /* control period, s; rounded to whole us (>= 1 us, <= 1000 s) */
    aocs_law_id_t law;            /* initial law; AOCS_LAW_NONE starts in STANDBY */
    aocs_exec_target_t target;    /* initial target; qd0 of a rotating target */
    aocs_vec3_t target_rotation_rate_D; /* rad/s, constant rate of D w.r.t. N in D; 0 = fixed target.
                                     * When non-zero, target.wd_B and target.wd_dot_B must be 0 (guidance computes them). */
    uint64_t target_t0_ns;        /* sensor time at which a rotating target equals target.qd_DN (lockstep: 0 = sim start) */
    aocs_exec_law_configs_t laws;
    aocs_vec3_t u_max_axis;       /* per-axis limit, N m (N); all 0 = unused, else all > 0 */
    real_t u_max_norm;            /* limit of |u|_2; 0 = unused. At least one limit must be set. */
    real_t k_safe;                /* safe-mode damping gain, N m s/rad, > 0 */
    uint32_t recover_good_samples;/* M: consecutive good samples to leave SAFE, >= 1 */
    uint32_t missing_max_periods; /* N: a gap of >= N missed samples enters SAFE, >= 1 */
    uint64_t stale_timeout_ns;    /* real-time mode: max age (HAL now - sensor time), > 0 there */
    uint64_t budget_ns;           /* step budget override; 0 = the law's BUDGET_NS (laws.def) */
    aocs_exec_clock_t clock;
    aocs_exec_guidance_config_t guidance; /* default: STEP mode */
    aocs_wheels_config_t wheels;  /* reaction wheel array; wheels.n = 0: none. Its period_s is set from
                                   * period_s at init (one source) */
} aocs_exec_config_t;

/* One sensor sample (lockstep: one per control period). */
typedef struct {
    uint32_t tick;                /* frame counter of the sample; gaps count as missing samples */
    uint64_t t_sensor_ns;         /* sensor time, ns; must advance. Real-time mode: HAL time base */
    uint32_t valid;               /* AOCS_EXEC_VALID_* flags */
    aocs_quat_t q_BN;             /* estimated attitude */
    aocs_vec3_t w_BN_B;           /* estimated body rate, rad/s */
    aocs_vec3_t pos_m;            /* orbit: position error [dx dy dz], m (SPEC 2.8) */
    aocs_vec3_t vel_mps;          /* orbit: velocity [du dv dw], m/s (SPEC 2.8) */
    real_t wheel_speed_radps[AOCS_WHEELS_MAX]; /* tachometers: wheel speeds relative to the body, rad/s
                                   * (read when a wheel array is configured) */
} aocs_exec_input_t;

/* Event counters (saturate at UINT32_MAX, never wrap). */
typedef struct {
    uint32_t steps;               /* step and step_no_input calls that produced an output */
    uint32_t invalid;             /* samples with NaN/Inf, non-unit q, or a needed validity flag off */
    uint32_t stale;               /* samples whose time did not advance or is older than the timeout */
    uint32_t missing;             /* missed samples (tick gaps and periods without a sample) */
    uint32_t law_error;           /* law step returned an error (e.g. CRP singular) */
    uint32_t overrun;             /* step time > budget */
    uint32_t mode_transitions;    /* every change of the actual mode */
    uint32_t saturated;           /* steps whose command was limited (or zeroed for NaN) */
    uint32_t select_accepted;
    uint32_t select_rejected;     /* unknown law, invalid target, invalid law config */
    uint64_t step_time_max_ns;    /* largest step time seen */
} aocs_exec_counters_t;

typedef struct {
    aocs_vec3_t u_cmd;            /* saturated command: torque N m (force N for orbit_lqr) */
    aocs_vec3_t u_unsat;          /* command before saturation (law or safe-mode output) */
    aocs_law_id_t law;            /* selected law */
    aocs_exec_mode_t mode;        /* actual mode of this step */
    aocs_status_t law_status;     /* status of the law step (AOCS_OK when not run) */
    aocs_status_t input_status;   /* AOCS_OK or why the sample was rejected (INPUT_*, QUAT_NOT_UNIT) */
    int saturated;                /* 1 when u_cmd != u_unsat */
    int overrun;                  /* 1 when step_time_ns > budget_ns */
    aocs_exec_target_t target;    /* target given to the law this step (rotating or slew: qd(t), wd_B,
                                   * wd_dot_B; wd_B and wd_dot_B only on a usable sample, else 0);
                                   * all zero from step_no_input (no law runs) */
    aocs_vec3_t u_ff;             /* slew feedforward added to the law's output this step (else 0), N m */
    uint64_t step_time_ns;        /* HAL time around guidance + law + saturation */
    uint32_t step_cycles;         /* aocs_hal_cycles() difference (0 where the platform has none) */
    uint64_t budget_ns;
    uint32_t tick;                /* tick of the sample (last tick for step_no_input) */
    aocs_exec_counters_t counters;
    aocs_wheels_alloc_t wheels;   /* wheel torque commands (all zero without an array) */
    aocs_wheels_momentum_t momentum; /* total momentum and speed margin (zero without an array) */
    aocs_status_t wheels_status;  /* AOCS_OK, or why the allocation gave a zero command */
} aocs_exec_output_t;

/* Law states (member STATE of every laws.def row), one of each so a rejected select leaves the active one untouched. */
#define AOCS_LAW_STATE_MEMBER(ID, NAME, INPUT, TITLE, STATE, STATE_T, ...) STATE_T STATE;
typedef struct {
    AOCS_LAW_ROWS(AOCS_LAW_STATE_MEMBER)
} aocs_exec_law_states_t;

/*
 * Direct dispatch to one law, without the executive's checks (law_table.c;
 * the executive, the bench and the tests use it).
 * aocs_exec_law_init initialises states->STATE of `law` from cfgs->CFG, the
 * variant forced by the law id: the law init's status, AOCS_ERR_UNKNOWN_LAW
 * for NONE / out of range, AOCS_ERR_NULL_ARG.
 * aocs_exec_law_step runs one step of `law` (att for attitude laws, orbit
 * for the orbit law; both must be given); *u is zeroed on any error.
 */
aocs_status_t aocs_exec_law_init(aocs_exec_law_states_t *states, const aocs_exec_law_configs_t *cfgs,
                                 aocs_law_id_t law);
aocs_status_t aocs_exec_law_step(aocs_exec_law_states_t *states, aocs_law_id_t law,
                                 const aocs_att_input_t *att, const aocs_orbit_input_t *orbit,
                                 aocs_vec3_t *u);

typedef struct {
    /* cached configuration */
    aocs_exec_config_t cfg;
    uint64_t period_ns;
    /* internal state */
    aocs_exec_law_states_t states;
    aocs_law_id_t law;            /* selected law */
    aocs_exec_target_t target;    /* fixed target, or qd0 of a rotating one */
    uint64_t target_t0_ns;        /* sensor time of qd0 (rotating target) */
    int target_rotating;          /* target_rotation_rate_D is non-zero */
    int slew_pending;             /* SLEW mode: a target was commanded, the slew starts at the next good sample */
    aocs_slew_t slew;             /* SLEW mode: the slew being flown (zero length before the first) */
    uint64_t slew_t0_ns;          /* sensor time of the slew's start */
    aocs_exec_mode_t mode;        /* actual mode */
    aocs_exec_mode_t requested;   /* STANDBY or NOMINAL, what SAFE returns to */
    uint32_t good_run;            /* consecutive good samples while in SAFE */
    uint32_t missing_run;         /* consecutive periods without a sample (step_no_input) */
    int have_sample;              /* a previous sample exists (tick/time reference valid) */
    uint32_t last_tick;
    uint64_t last_t_sensor_ns;
    aocs_vec3_t last_u_cmd;       /* held by step_no_input below the missing threshold */
    aocs_exec_counters_t counters;
    int initialised;
    /* frame acceptance (end of this file): the resynchronisation candidates */
    uint32_t resync_run;          /* consecutive rejected samples, each continuing the one before (< K) */
    uint32_t resync_tick;         /* tick and sensor time of the last of them */
    uint64_t resync_t_ns;
    uint32_t resyncs;             /* resynchronisations so far (saturates at UINT32_MAX) */
    /* reaction wheel array (wheels.c) */
    aocs_wheels_t wheels;         /* initialised only when cfg.wheels.n != 0 */
    real_t wheel_speed_last[AOCS_WHEELS_MAX]; /* tachometer speeds of the last sample (step_no_input) */
    aocs_vec3_t w_last_B;         /* body rate of the last sample (momentum in step_no_input) */
} aocs_exec_t;

/*
 * Defaults: period 0.1 s, AOCS_LAW_NONE, identity target, no limits set
 * (the caller must set one), k_safe 1, M = 10, N = 3, stale timeout
 * 2 periods, no budget override, lockstep. Law configs zeroed (invalid).
 * No wheel array (wheels.n = 0) with the array's own defaults
 * (aocs_wheels_config_default: no friction model, no null-space management).
 * Total (no-op on NULL).
 */
void aocs_exec_config_default(aocs_exec_config_t *cfg);

/*
 * Validates the config and initialises the selected law with its config.
 * Status: AOCS_ERR_NULL_ARG; AOCS_ERR_RATE_INVALID (period not finite or out
 * of range); AOCS_ERR_UNKNOWN_LAW; AOCS_ERR_TARGET_INVALID (non-finite or
 * non-unit qd, non-finite wd/wd_dot, non-finite target_rotation_rate_D, or
 * a rotating target with a non-zero wd/wd_dot); AOCS_ERR_PARAM_NOT_FINITE (limit,
 * k_safe); AOCS_ERR_SAT_LIMIT_NOT_POSITIVE (negative limit, mixed zero and
 * non-zero per-axis limits, or no limit set); AOCS_ERR_GAIN_NOT_POSITIVE
 * (k_safe <= 0, M or N == 0, real-time stale timeout == 0);
 * AOCS_ERR_MODE_INVALID (clock out of range); AOCS_ERR_GUIDANCE_MODE_INVALID
 * (guidance.mode out of range); in SLEW mode AOCS_ERR_GUIDANCE_TARGET_MOVING
 * (rotating target or non-zero wd/wd_dot) and the slew config's codes
 * (aocs_slew_config_check: profile, margin, rate limit, jerk time, inertia);
 * the wheel array's own status (aocs_wheels_init) when cfg.wheels.n != 0;
 * else the law init's own status. The selected law's state is reset (its init
 * re-run from the cached config) on every target change (select with a
 * target) and on every change into NOMINAL, so integral states start at zero.
 * On any error exec is left not initialised (step returns
 * AOCS_ERR_NOT_INITIALISED with a zero command).
 */
aocs_status_t aocs_exec_init(aocs_exec_t *exec, const aocs_exec_config_t *cfg);

/*
 * Run-time command: select law (AOCS_LAW_NONE = STANDBY) and target (NULL
 * keeps the current target). A new law is (re)initialised from the stored
 * config. With a rotating target (cfg.target_rotation_rate_D != 0) the new
 * target is qd0 from the time of the last sample on (t0 = that sensor time;
 * before any sample t0 is kept), and its wd/wd_dot must be zero. Rejected,
 * counted in select_rejected, and nothing changed on:
 * AOCS_ERR_UNKNOWN_LAW, AOCS_ERR_TARGET_INVALID, or the law init's status.
 * Selecting a law requests NOMINAL; if the executive is in SAFE it stays
 * there until the recovery rule is met. Selecting NONE enters STANDBY at once.
 */
aocs_status_t aocs_exec_select(aocs_exec_t *exec, aocs_law_id_t law, const aocs_exec_target_t *target);

/*
 * One control step on a sensor sample. Returns AOCS_OK when a command was
 * produced (whatever the mode: a rejected input is reported in
 * out->input_status and handled by SAFE, not by an error return);
 * AOCS_ERR_NULL_ARG / AOCS_ERR_NOT_INITIALISED otherwise (then *out, if
 * given, holds a zero command).
 */
aocs_status_t aocs_exec_step(aocs_exec_t *exec, const aocs_exec_input_t *in, aocs_exec_output_t *out);

/*
 * Real-time mode: the period ended without a sample. Counts one missing
 * sample; below N consecutive missing periods the last command is held
 * (zero-order hold), from N on the executive is in SAFE with a zero command
 * (no fresh rate to damp). input_status = AOCS_ERR_INPUT_MISSING.
 */
aocs_status_t aocs_exec_step_no_input(aocs_exec_t *exec, aocs_exec_output_t *out);

/*
 * Sets t0 of a rotating target: the sensor time at which it equals its qd0
 * (real-time mode: the sensor time base is the HAL clock, so the adapter maps
 * the plant's time 0 onto it). AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED.
 */
aocs_status_t aocs_exec_set_target_epoch(aocs_exec_t *exec, uint64_t t0_ns);

/* Counters so far (zeroed struct on NULL args). Total. */
aocs_exec_counters_t aocs_exec_counters(const aocs_exec_t *exec);

/* ---- real-time period timer (timing.c), pure integer arithmetic ---- */
typedef struct {
    uint64_t period_ns;
    uint64_t t0_ns;               /* ideal start of period 0 */
    uint64_t k;                   /* index of the next period to start */
    uint64_t periods;             /* periods started */
    uint64_t slips;               /* periods skipped because the start came a period or more late */
    int64_t jitter_last_ns;       /* actual start - ideal start of the last period */
    uint64_t jitter_max_abs_ns;
    real_t jitter_ms_ns2;         /* running mean of jitter^2, ns^2 */
} aocs_exec_timer_t;

/*
 * Ideal start of period k is t0 + k * period (absolute: no drift).
 * AOCS_ERR_NULL_ARG, AOCS_ERR_RATE_INVALID when period_ns == 0.
 */
aocs_status_t aocs_exec_timer_init(aocs_exec_timer_t *tmr, uint64_t period_ns, uint64_t t0_ns);

/*
 * Records that a period started at now_ns: jitter = now - ideal start; when
 * now is one or more whole periods late those periods are counted as slips
 * and skipped (the phase is kept). Writes the absolute deadline of the next
 * period start (t0 + (k+1) * period) to *next_deadline_ns.
 */
aocs_status_t aocs_exec_timer_period_start(aocs_exec_timer_t *tmr, uint64_t now_ns, uint64_t *next_deadline_ns);

/* RMS of the recorded jitter, ns (0 before the first period). Total. */
real_t aocs_exec_timer_jitter_rms_ns(const aocs_exec_timer_t *tmr);

/* Period in ns from seconds, rounded to whole microseconds; AOCS_ERR_RATE_INVALID when out of [1 us, 1000 s]. */
aocs_status_t aocs_exec_period_to_ns(real_t period_s, uint64_t *period_ns);

/* Host budget of safe/standby steps (no law), ns. */
#define AOCS_EXEC_SAFE_BUDGET_NS 2000u

/*
 * Host budget added to an attitude law's step in guidance mode SLEW, ns: the
 * slew reference (closed-form profile, qd(t), the rotation of the rates into
 * B) and the feedforward. Measured with callgrind on the host (double,
 * irassi_large quat_pd, 13000 steps): +1870 instructions per step over the
 * same step in STEP mode (3390 against 1520), i.e. more than a whole quat_pd
 * step, whose budget is 2000 ns; the allowance is that budget again.
 */
#define AOCS_EXEC_SLEW_BUDGET_NS 2000u

/*
 * ---- Frame acceptance (executive.c; docs/wire-contract.md "Frame acceptance") ----
 * No single sample can move the tick/time reference of aocs_exec_step far.
 * With T the period, K = AOCS_EXEC_RESYNC_FRAMES, G = AOCS_EXEC_TICK_JUMP_MAX,
 * a sample b continues a sample a when
 *     g = b.tick - a.tick (modulo 2^32) is in [1, G], and
 *     lockstep:  |(b.t - a.t) - g T| <= T / AOCS_EXEC_LOCKSTEP_TOL_DIV
 *                (sensor time advances by the ticks' periods, within T / 4),
 *     real time: b.t > a.t.
 * Real time only: every sample must also lie on the HAL clock within
 * [now - stale_timeout_ns, now + T]; one outside is stale and nothing else.
 *
 * A sample that continues the reference (the last accepted sample) is
 * accepted and becomes the reference (a gap g > 1 counts g - 1 missing). The
 * first sample after init is accepted as it is. Any other sample is stale
 * (counted, SAFE, reference untouched) and a resynchronisation candidate:
 * K consecutive candidates, each continuing the one before, resynchronise;
 * the K-th becomes the reference and is treated as accepted (no missing
 * counted for the jump; exec.resyncs counts them). An accepted sample drops
 * the candidates. So one bad sample (any tick, any time, first one or not)
 * costs itself and at most K - 1 later good samples: the executive is
 * NOMINAL again at the latest with the (K - 1 + M)-th good sample after it
 * (M = recover_good_samples), and with the M-th when the bad sample did not
 * continue the reference.
 *
 * K = 3: one bad sample can never resynchronise, two forged samples that
 * agree with each other cannot either, and a plant that really restarts its
 * tick or time is followed after 3 samples (0.3 s at 10 Hz).
 */
#define AOCS_EXEC_RESYNC_FRAMES 3u
/* Largest tick step that continues the reference: 1024 periods (102 s at 10 Hz),
 * far beyond any real loss burst (N missing samples already enter SAFE). */
#define AOCS_EXEC_TICK_JUMP_MAX 1024u
/* Lockstep: sensor time must advance by g periods within T / 4. Any tolerance
 * below T / 2 keeps tick and time unambiguous; T / 4 leaves room for the
 * plant's rounding (t_s = k dt in double, ns rounding) and nothing else. */
#define AOCS_EXEC_LOCKSTEP_TOL_DIV 4u

/*
 * Accepted range of every actuator limit (u_max_axis components and
 * u_max_norm when set), N m for torque and N for force; aocs_exec_init gives
 * AOCS_ERR_SAT_LIMIT_NOT_POSITIVE for a limit outside it. 1e-9 is three orders
 * below the smallest actuator a spacecraft flies (micro-thrusters and
 * magnetorquers of 1e-6 N or N m): a smaller limit is a unit mistake. 1e9 is
 * the project's "effectively unlimited" value (aocs_core.limits.UNLIMITED,
 * written when a scenario sets no limit) and six orders above the largest
 * attitude actuators (CMGs of ~1e3 N m). Inside this range every square and
 * sum of squares the saturation forms is a normal number in float and in
 * double (1e-18 >> FLT_MIN, 3e18 << FLT_MAX), so the limiting is exact.
 */
#define AOCS_EXEC_U_LIMIT_MIN AOCS_R(1.0e-9)
#define AOCS_EXEC_U_LIMIT_MAX AOCS_R(1.0e9)

/*
 * Accepted control period, whole microseconds (aocs_exec_period_to_ns):
 * 1 us (a 1 MHz loop, far above any attitude loop) to 1000 s (slower is not
 * a control loop). The scenario loader reads both from the build's registry
 * (tools/registry), so it cannot accept a rate the executive refuses.
 */
#define AOCS_EXEC_PERIOD_MIN_US AOCS_R(1.0)
#define AOCS_EXEC_PERIOD_MAX_US AOCS_R(1.0e9)

#endif /* AOCS_EXECUTIVE_H */
