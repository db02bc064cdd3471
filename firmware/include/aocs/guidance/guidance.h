/*
 * The guidance stage (ARCHITECTURE.md "The flight pipeline"): from the
 * commanded target and the attitude estimate, the target the control law
 * sees this step (qd, wd_B, wd_dot_B), by one of the modes of
 * aocs/guidance/guidance_modes.def (one table, one row per mode).
 *
 *   aocs_guidance_check(&cfg.guidance, &cfg.target, cfg.target_rotation_rate_D)  at init
 *   aocs_guidance_init(&g, &cfg.guidance, &cfg.target, rate_D, t0, limits)
 *   aocs_guidance_command(&g, &target, have_sample, t_last_ns)   a new target
 *   loop: aocs_guidance_step(&g, &gin, &target)                 attitude laws
 *
 * Modes (docs/spec.md "Slew guidance", SPEC 5.1):
 *   STEP      the law sees the commanded target at once (the reference
 *             papers' runs, bit for bit);
 *   ROTATING  a target frame D that rotates at the constant rate rate_D (rad/s,
 *             in D) relative to N: from the sensor time t (exact closed form,
 *             no accumulated drift)
 *                 qd(t) = dq(w (t - t0)) (x) qd0,  dq(theta) = [sin(|theta|/2) theta/|theta|; cos(|theta|/2)]
 *             (the solution of qd' = 0.5 Xi(qd) w, the plant's Plant.target(t)), and
 *                 wd_B = A(qe) w,  qe = q (x) qd^-1   (D's rate in B: we = w - wd_B)
 *                 wd_dot_B = wd_B x w_BN_B           (d/dt of the B components, rotating.c)
 *             qd0 is the commanded target, t0 its epoch (lockstep: sim time 0;
 *             a new target becomes qd0 at the time of the last sample);
 *   SLEW      a commanded target starts a rest-to-rest eigenaxis slew from the
 *             attitude of the next usable sample (aocs/guidance/slew.h); the
 *             law tracks qd(t), wd_B(t), wd_dot_B(t) (the profile's D-frame
 *             rates rotated into B by A(qe), wd_dot_B the derivative of those
 *             B components), and the executive adds
 *                 u_ff = J wd_dot_B + wd_B x (J wd_B + h_wheels)
 *             to every law not in AOCS_LAW_FEEDFORWARD_IN_FORMULA (laws.def).
 *             The envelope is the executive's limits (u_max_axis, u_max_norm)
 *             and the wheel array. A slew needs a fixed target.
 * Orbit laws ignore guidance (they regulate to zero).
 */
#ifndef AOCS_GUIDANCE_GUIDANCE_H
#define AOCS_GUIDANCE_GUIDANCE_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/math3.h"
#include "aocs/actuation/wheel_array.h"
#include "aocs/guidance/slew.h"
#include "aocs/guidance/guidance_modes.def"
#include "aocs/exec/io.h"
#include "aocs/estimation/determination.h"

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
/* ---- the table of modes (guidance_modes.def) ---- */
#define AOCS_GUIDANCE_ENUM_ROW(ID, ...) AOCS_GUIDANCE_##ID,
typedef enum {
    AOCS_GUIDANCE_ROWS(AOCS_GUIDANCE_ENUM_ROW)
    AOCS_GUIDANCE_COUNT
} aocs_guidance_id_t;

/* The state of the stage. */
typedef struct {
    aocs_guidance_id_t id;        /* the row flown (aocs_guidance_resolve of the configuration) */
    aocs_exec_guidance_config_t cfg; /* cached configuration */
    aocs_vec3_t rate_D;           /* ROTATING: constant rate of D w.r.t. N in D, rad/s */
    aocs_vec3_t u_max_axis;       /* SLEW: the torque envelope, the executive's limits */
    real_t u_max_norm;
    aocs_exec_target_t target;    /* commanded target (ROTATING: qd0) */
    uint64_t target_t0_ns;        /* sensor time of qd0 (ROTATING) */
    int slew_pending;             /* PLANNED rows: a target was commanded, planned at the next usable sample */
    aocs_slew_t slew;             /* SLEW: the slew being flown (zero length before the first) */
    uint64_t slew_t0_ns;          /* sensor time of the slew's start */
    /* SLEW after an actuator loss (aocs_guidance_slow_down, docs/spec.md 5.15.2): the profile's time runs at
     * time_scale from profile time scale_tau0_s at sensor time scale_t0_ns; not scaled: the elapsed time */
    int scaled;
    real_t time_scale;            /* k in (0, 1] */
    real_t scale_tau0_s;
    uint64_t scale_t0_ns;
} aocs_guidance_t;

/* What a step sees besides its state. */
typedef struct {
    uint64_t t_ns;                   /* sensor time of the sample */
    const aocs_det_output_t *est;    /* attitude estimate of this step (determination stage) */
    int usable;                      /* 1: est is usable this step (the law runs on it) */
    int law_active;                  /* 1: a law is selected (a plan waits for one) */
    const aocs_wheels_t *wheels;     /* the wheel array (SLEW envelope), NULL without one */
} aocs_guidance_input_t;

/* The row a configuration selects: guidance.mode, and for STEP a non-zero rate_D selects ROTATING. Total. */
aocs_guidance_id_t aocs_guidance_resolve(const aocs_exec_guidance_config_t *gcfg, aocs_vec3_t rate_D);

/* Name of a row ("step", "rotating", "slew"); "unknown" out of range. Total. */
const char *aocs_guidance_name(aocs_guidance_id_t id);

/*
 * Configuration check (aocs_exec_init, after the target and limit checks):
 * AOCS_ERR_NULL_ARG; AOCS_ERR_GUIDANCE_MODE_INVALID (guidance.mode out of
 * range); then the resolved row's CHECK (SLEW: AOCS_ERR_GUIDANCE_TARGET_MOVING
 * for a rotating target or a non-zero wd/wd_dot, and aocs_slew_config_check's codes).
 */
aocs_status_t aocs_guidance_check(const aocs_exec_guidance_config_t *gcfg, const aocs_exec_target_t *target,
                                  aocs_vec3_t rate_D);

/* Initialises the stage from a checked configuration (no check here). Total (no-op on NULL). */
void aocs_guidance_init(aocs_guidance_t *g, const aocs_exec_guidance_config_t *gcfg,
                        const aocs_exec_target_t *target, aocs_vec3_t rate_D, uint64_t t0_ns,
                        aocs_vec3_t u_max_axis, real_t u_max_norm);

/* 1 when the flown row computes wd/wd_dot itself (OWN_RATES): a commanded target must give zero ones. Total. */
int aocs_guidance_owns_rates(const aocs_guidance_t *g);

/*
 * A commanded target (checked by the caller): the new target (ROTATING: qd0
 * from t_last_ns on when have_sample, else t0 kept); a PLANNED row plans it
 * from the next usable sample. Total.
 */
void aocs_guidance_command(aocs_guidance_t *g, const aocs_exec_target_t *target, int have_sample,
                           uint64_t t_last_ns);

/* The epoch of a rotating target's qd0 (aocs_exec_set_target_epoch). Total. */
void aocs_guidance_set_epoch(aocs_guidance_t *g, uint64_t t0_ns);

/*
 * The actuators lost torque (fault management isolated a wheel, docs/spec.md 5.15.2): a slew in progress
 * at sensor time t_ns (a PLANNED row, planned, t_ns before its end) flies the rest of its profile on a
 * slower clock, profile time tau = tau(t_ns) + k (t - t_ns): the same path, rates times k, accelerations
 * times k^2, so with k = sqrt(alpha_new / alpha_old) (the envelopes along the slew's eigenaxis) it asks no
 * more of the actuators left than the plan asked of the full set, and the rate at the switch changes
 * only by the factor k (a rest-to-rest replan from a moving body would ask the law to stop it first).
 * k outside (0, 1] or not finite, or nothing in progress: no-op. Total.
 */
void aocs_guidance_slow_down(aocs_guidance_t *g, uint64_t t_ns, real_t k);

/* SLEW: the profile time of sensor time t_ns (the elapsed time since the slew's start, or the slowed clock
 * of aocs_guidance_slow_down), s. 0 on NULL. Total. */
real_t aocs_guidance_profile_time_s(const aocs_guidance_t *g, uint64_t t_ns);

/*
 * The target an attitude law sees this step (the row's STEP), into *target:
 * wd_B and wd_dot_B only on a usable estimate, else 0. On NULL arguments
 * (target given) the identity with zero rates. Total.
 */
void aocs_guidance_step(aocs_guidance_t *g, const aocs_guidance_input_t *in, aocs_exec_target_t *target);

/* 1 when the executive adds the row's feedforward to an attitude law without its own (FEEDFORWARD). Total. */
int aocs_guidance_has_feedforward(const aocs_guidance_t *g);

/* SPEC 5.1: u_ff = J wd_dot + wd x (J wd + h_wheels), J the slew config's inertia. Total. */
aocs_vec3_t aocs_guidance_feedforward(const aocs_guidance_t *g, const aocs_exec_target_t *target,
                                      aocs_vec3_t h_wheels_B);

/* Host budget the row adds to an attitude law's step, ns (BUDGET_NS). Total (0 on NULL). */
uint64_t aocs_guidance_budget_ns(const aocs_guidance_t *g);

/* ---- the rows' functions (guidance_modes.def), declared from the rows ---- */
#define AOCS_GUIDANCE_PROTOTYPES(ID, NAME, CHECK, STEP, ...)                                                   \
    aocs_status_t CHECK(const aocs_exec_guidance_config_t *gcfg, const aocs_exec_target_t *target,            \
                        aocs_vec3_t rate_D);                                                                  \
    void STEP(aocs_guidance_t *g, const aocs_guidance_input_t *in, aocs_exec_target_t *target);
AOCS_GUIDANCE_ROWS(AOCS_GUIDANCE_PROTOTYPES)

/* ---- helpers the rows share ---- */
/* 1 when any component is non-zero (exact test, no tolerance). Total. */
int aocs_guidance_vec_nonzero(aocs_vec3_t w);

/* Rotating-target attitude qd(t) = dq(w dt) (x) qd0 (rotating.c). Total. */
aocs_quat_t aocs_guidance_rotating_attitude(aocs_quat_t qd0_DN, aocs_vec3_t w_DN_D, real_t dt_s);

/*
 * wd_B = A(qe) w, wd_dot_B = wd_B x w_BN_B for a target rotating at w (in D),
 * qe = q (x) qd^-1 normalised (rotating.c); zero when qe cannot be
 * normalised. NULL outputs are skipped. Total.
 */
void aocs_guidance_rotating_rates(aocs_quat_t q_BN, aocs_quat_t qd_DN, aocs_vec3_t w_DN_D, aocs_vec3_t w_BN_B,
                                  aocs_vec3_t *wd_B, aocs_vec3_t *wd_dot_B);

/*
 * Slew reference rates in B: with qe = q (x) qd^-1 normalised and A = A(qe) = A_BD,
 *     wd_B = A wd_D,  wd_dot_B = A wd_dot_D + wd_B x w_BN_B
 * (d/dt of the B components: dA/dt = -[(w - wd_B) x] A, as for the rotating
 * target, plus the profile's own acceleration). Zero when qe cannot be
 * normalised. NULL outputs are skipped. Total.
 */
void aocs_guidance_slew_rates(aocs_quat_t q_BN, aocs_quat_t qd_DN, aocs_vec3_t wd_D, aocs_vec3_t wd_dot_D,
                              aocs_vec3_t w_BN_B, aocs_vec3_t *wd_B, aocs_vec3_t *wd_dot_B);

/* t - t0 in seconds, negative when t < t0, without forming a huge real ns count. Total. */
real_t aocs_guidance_elapsed_s(uint64_t t_ns, uint64_t t0_ns);

#endif /* AOCS_GUIDANCE_GUIDANCE_H */
