/*
 * The attitude-determination stage (ARCHITECTURE.md "The flight pipeline"):
 * from the accepted sensor sample, the attitude and rate estimate the
 * guidance and the control law use, by one of the estimators of
 * aocs/estimation/determination.def, selected by the configuration key
 * "estimator" (config_fields.def; 0 = passthrough).
 *
 *   aocs_det_init(&det, &cfg.determination)     validates the selection, inits its state
 *   loop: aocs_det_step(&det, &in, accept_status, dt_s, &est)
 *   aocs_det_reset(&det)                         the state afresh (same configuration)
 *
 * The output's status is AOCS_OK when q_BN and w_BN_B may drive the law this
 * step; otherwise the reason (the executive then flies SAFE). valid holds the
 * AOCS_EXEC_VALID_ATT / _RATE flags of the estimate (SAFE damps with w_BN_B
 * when its RATE flag is set and it is finite).
 *
 * PASSTHROUGH (passthrough.c): the measured q and w as they are, with the
 * input acceptance's verdict as status.
 * MEKF (mekf_stage.c, the filter in mekf.c; docs/spec.md 5.6.11): propagates
 * with the gyro, updates with a star-tracker sample when one is offered;
 * status AOCS_OK once it holds an estimate, AOCS_ERR_MEKF_NO_ATTITUDE while
 * it waits for its first tracker sample (SAFE, damping on the gyro rate
 * minus the bias estimate), a rejected tracker sample only counted.
 *
 * Each row names the validity flags its sample must carry (NEEDS,
 * aocs_det_needs): the input acceptance checks those for attitude laws.
 */
#ifndef AOCS_ESTIMATION_DETERMINATION_H
#define AOCS_ESTIMATION_DETERMINATION_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/math3.h"
#include "aocs/exec/io.h"
#include "aocs/estimation/estimate.h"
#include "aocs/estimation/determination.def"

#define AOCS_DET_ENUM_ROW(ID, ...) AOCS_DET_##ID,
typedef enum {
    AOCS_DETERMINATION_ROWS(AOCS_DET_ENUM_ROW)
    AOCS_DET_COUNT
} aocs_det_id_t;

/* Configuration of the stage (aocs_exec_config_t.determination): the selection, then each estimator's own. */
#define AOCS_DET_CFG_DECL_CFG_OWN(CFG_T, CFG) CFG_T CFG;
#define AOCS_DET_CFG_DECL_CFG_NONE(CFG_T, CFG)
#define AOCS_DET_CONFIG_MEMBER(ID, NAME, STATE, STATE_T, CFG_USE, CFG, CFG_T, ...) AOCS_DET_CFG_DECL_##CFG_USE(CFG_T, CFG)
typedef struct {
    uint32_t estimator;           /* aocs_det_id_t value (key "estimator"); default 0 = PASSTHROUGH */
    AOCS_DETERMINATION_ROWS(AOCS_DET_CONFIG_MEMBER)
} aocs_det_config_t;


/* One state of each estimator (member STATE of every row). */
#define AOCS_DET_STATE_MEMBER(ID, NAME, STATE, STATE_T, ...) STATE_T STATE;
typedef struct {
    AOCS_DETERMINATION_ROWS(AOCS_DET_STATE_MEMBER)
} aocs_det_states_t;

typedef struct {
    aocs_det_id_t id;             /* the selected estimator */
    aocs_det_config_t cfg;        /* cached configuration (reset) */
    aocs_det_states_t states;
    int initialised;
} aocs_det_t;

/* Name of an estimator ("passthrough"); "unknown" out of range. Total. */
const char *aocs_det_name(aocs_det_id_t id);

/* AOCS_ERR_NULL_ARG; AOCS_ERR_ESTIMATOR_UNKNOWN (estimator out of range); else the estimator's init. */
aocs_status_t aocs_det_init(aocs_det_t *det, const aocs_det_config_t *cfg);

/* The selected estimator's state afresh from the cached configuration. AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED. */
aocs_status_t aocs_det_reset(aocs_det_t *det);

/*
 * One step on the sensor sample in (accept_status: the input acceptance's
 * verdict on it), dt_s the control period. *out is always written (on an
 * error: q identity, w zero, valid 0, status the error). AOCS_ERR_NULL_ARG,
 * AOCS_ERR_NOT_INITIALISED, else the estimator's own status.
 */
aocs_status_t aocs_det_step(aocs_det_t *det, const aocs_exec_input_t *in, aocs_status_t accept_status, real_t dt_s,
                            aocs_det_output_t *out);

/* Fault management (docs/spec.md 5.15.3): excluded != 0 makes a filter that takes the star tracker test its
 * samples without applying them (the MEKF: aocs_mekf_set_st_excluded); no-op for an estimator without one,
 * and on NULL. */
void aocs_det_set_st_excluded(aocs_det_t *det, uint32_t excluded);

/* Fault management (docs/spec.md 5.15.3): the star tracker's noise variances the filter assumes, times scale
 * (>= 1; the MEKF: aocs_mekf_set_st_noise_scale); no-op for an estimator without one, and on NULL. */
void aocs_det_set_st_noise_scale(aocs_det_t *det, real_t scale);

/* Fault management (docs/spec.md 5.15.4): a filter that estimates the gyro's bias takes its bias covariance
 * back to its prior (the MEKF: aocs_mekf_reinflate_bias); no-op for an estimator without one, and on NULL. */
void aocs_det_reinflate_bias(aocs_det_t *det);

/* The gyro rate random walk sigma_u (rad/s^1.5) the selected filter assumes; 0 for an estimator without a
 * bias state, and on NULL (the fault management's bias-jump test is then off). Total. */
real_t aocs_det_gyro_rrw(const aocs_det_t *det);

/* Fault management (docs/spec.md 5.6.12, 5.15.4): 1 when the selected estimator can go on without its gyro
 * (the MEKF with mekf.gyroless_torque_sigma_nm > 0), else 0. Total. */
uint32_t aocs_det_gyroless_capable(const aocs_det_t *det);

/* The gyro excluded: the estimator propagates on the rigid-body dynamics of the inertia J from the next step
 * (aocs_mekf_set_gyroless, from the rate it last gave). AOCS_OK; AOCS_ERR_NULL_ARG;
 * AOCS_ERR_MEKF_NOISE_NOT_POSITIVE for an estimator without a gyroless model; else the MEKF's refusal. */
aocs_status_t aocs_det_set_gyroless(aocs_det_t *det, const aocs_mat3_t *inertia_B_kgm2);

/* 1 once the estimator propagates without its gyro (aocs_det_set_gyroless succeeded). Total. */
uint32_t aocs_det_is_gyroless(const aocs_det_t *det);

/* The body torque commanded for the coming period and the wheels' momentum, for a gyroless propagation
 * (aocs_mekf_set_torque); no-op for an estimator that does not use them, and on NULL. */
void aocs_det_set_torque(aocs_det_t *det, aocs_vec3_t tau_B_Nm, aocs_vec3_t h_wheels_B_Nms);

/* The AOCS_EXEC_VALID_* flags an attitude sample must carry for estimator id (its row's NEEDS): what the
 * input acceptance checks (exec/acceptance.h). ATT|RATE out of range (the passthrough's, the conservative
 * choice). Total. */
uint32_t aocs_det_needs(aocs_det_id_t id);

/* Host budget the selected estimator adds to a step, ns (BUDGET_NS). Total (0 on NULL). */
uint64_t aocs_det_budget_ns(const aocs_det_t *det);

/* ---- the rows' functions (determination.def), declared from the rows ---- */
#define AOCS_DET_PROTOTYPES(ID, NAME, STATE, STATE_T, CFG_USE, CFG, CFG_T, INIT, STEP, ...)                   \
    aocs_status_t INIT(STATE_T *s, const aocs_det_config_t *cfg);                                            \
    aocs_status_t STEP(STATE_T *s, const aocs_exec_input_t *in, aocs_status_t accept_status, real_t dt_s,    \
                       aocs_det_output_t *out);
AOCS_DETERMINATION_ROWS(AOCS_DET_PROTOTYPES)

#endif /* AOCS_ESTIMATION_DETERMINATION_H */
