/*
 * The attitude-determination stage (aocs/estimation/determination.h): names,
 * init/reset and the dispatch to the selected estimator, all expanded from
 * the rows of aocs/estimation/determination.def (nothing here names one).
 */
#include <stddef.h>
#include <string.h>

#include "aocs/executive.h"

#define DET_NAME_ROW(ID, NAME, ...) (NAME),
#define DET_BUDGET_ROW(ID, NAME, STATE, STATE_T, CFG_USE, CFG, CFG_T, INIT, STEP, BUDGET_NS, ...) (uint64_t)(BUDGET_NS),
#define DET_NEEDS_ROW(ID, NAME, STATE, STATE_T, CFG_USE, CFG, CFG_T, INIT, STEP, BUDGET_NS, INSTR_M4F, INSTR_M7, NEEDS) \
    (NEEDS),

static int det_id_in_range(aocs_det_id_t id)
{
    return (((int)id >= 0) && (id < AOCS_DET_COUNT)) ? 1 : 0;
}

const char *aocs_det_name(aocs_det_id_t id)
{
    static const char *const det_names[AOCS_DET_COUNT] = {AOCS_DETERMINATION_ROWS(DET_NAME_ROW)};
    const char *name = "unknown";
    if (det_id_in_range(id) != 0) {
        name = det_names[id];
    }
    return name;
}

#define DET_INIT_CASE(ID, NAME, STATE, STATE_T, CFG_USE, CFG, CFG_T, INIT, STEP, ...) \
    case AOCS_DET_##ID:                                     \
        st = INIT(&det->states.STATE, &det->cfg);           \
        break;

/* (Re)initialises the selected estimator's state from the cached configuration. */
static aocs_status_t det_init_selected(aocs_det_t *det)
{
    aocs_status_t st = AOCS_ERR_ESTIMATOR_UNKNOWN;
    switch (det->id) {
    AOCS_DETERMINATION_ROWS(DET_INIT_CASE)
    default:
        st = AOCS_ERR_ESTIMATOR_UNKNOWN;
        break;
    }
    return st;
}

aocs_status_t aocs_det_init(aocs_det_t *det, const aocs_det_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (det != NULL) {
        (void)memset(det, 0, sizeof(*det));
    }
    if ((det == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (cfg->estimator >= (uint32_t)AOCS_DET_COUNT) {
        st = AOCS_ERR_ESTIMATOR_UNKNOWN;
    } else {
        det->cfg = *cfg;
        det->id = (aocs_det_id_t)cfg->estimator;
        st = det_init_selected(det);
        if (st == AOCS_OK) {
            det->initialised = 1;
        }
    }
    return st;
}

aocs_status_t aocs_det_reset(aocs_det_t *det)
{
    aocs_status_t st = AOCS_OK;
    if (det == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (det->initialised == 0) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        st = det_init_selected(det);
    }
    return st;
}

#define DET_STEP_CASE(ID, NAME, STATE, STATE_T, CFG_USE, CFG, CFG_T, INIT, STEP, ...) \
    case AOCS_DET_##ID:                                                   \
        st = STEP(&det->states.STATE, in, accept_status, dt_s, out);      \
        break;

aocs_status_t aocs_det_step(aocs_det_t *det, const aocs_exec_input_t *in, aocs_status_t accept_status, real_t dt_s,
                            aocs_det_output_t *out)
{
    aocs_status_t st = AOCS_OK;
    int dispatched = 0;
    if (out != NULL) {
        /* what an estimator does not write is zero (a passthrough has no covariance), no sample offered */
        (void)memset(out, 0, sizeof(*out));
        out->q_BN = aocs_quat_identity();
        out->st_status = AOCS_ERR_INPUT_MISSING;
    }
    if (out == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if ((det == NULL) || (in == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (det->initialised == 0) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        dispatched = 1;
        switch (det->id) {
        AOCS_DETERMINATION_ROWS(DET_STEP_CASE)
        default:
            st = AOCS_ERR_ESTIMATOR_UNKNOWN;
            dispatched = 0;
            break;
        }
    }
    if ((out != NULL) && (st != AOCS_OK) && (dispatched == 0)) {
        /* an error of the stage itself: nothing usable (an estimator's own status stands with what it
         * wrote: e.g. the MEKF waiting for its first tracker sample still gives SAFE a gyro rate) */
        out->q_BN = aocs_quat_identity();
        out->w_BN_B = aocs_vec3_zero();
        out->valid = 0u;
        out->status = st;
    }
    return st;
}

uint32_t aocs_det_needs(aocs_det_id_t id)
{
    static const uint32_t det_needs[AOCS_DET_COUNT] = {AOCS_DETERMINATION_ROWS(DET_NEEDS_ROW)};
    uint32_t needs = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
    if (det_id_in_range(id) != 0) {
        needs = det_needs[id];
    }
    return needs;
}

uint64_t aocs_det_budget_ns(const aocs_det_t *det)
{
    static const uint64_t det_budget_ns[AOCS_DET_COUNT] = {AOCS_DETERMINATION_ROWS(DET_BUDGET_ROW)};
    uint64_t budget = 0u;
    if ((det != NULL) && (det_id_in_range(det->id) != 0)) {
        budget = det_budget_ns[det->id];
    }
    return budget;
}

void aocs_det_reinflate_bias(aocs_det_t *det)
{
    if ((det != NULL) && (det->id == AOCS_DET_MEKF)) {
        aocs_mekf_reinflate_bias(&det->states.mekf);
    }
}

real_t aocs_det_gyro_rrw(const aocs_det_t *det)
{
    real_t rrw = AOCS_R(0.0);
    if ((det != NULL) && (det->id == AOCS_DET_MEKF) && (det->states.mekf.initialised != 0)) {
        rrw = det->states.mekf.cfg.gyro_rrw_radps1p5;
    }
    return rrw;
}

void aocs_det_set_st_excluded(aocs_det_t *det, uint32_t excluded)
{
    if ((det != NULL) && (det->id == AOCS_DET_MEKF)) {
        aocs_mekf_set_st_excluded(&det->states.mekf, excluded);
    }
}

uint32_t aocs_det_gyroless_capable(const aocs_det_t *det)
{
    uint32_t capable = 0u;
    if ((det != NULL) && (det->id == AOCS_DET_MEKF) && (det->states.mekf.initialised != 0) &&
        (det->states.mekf.cfg.gyroless_torque_sigma_nm > AOCS_R(0.0))) {
        capable = 1u;
    }
    return capable;
}

aocs_status_t aocs_det_set_gyroless(aocs_det_t *det, const aocs_mat3_t *inertia_B_kgm2)
{
    aocs_status_t st = AOCS_ERR_NULL_ARG;
    if (det != NULL) {
        st = AOCS_ERR_MEKF_NOISE_NOT_POSITIVE; /* an estimator without a gyroless model */
        if (det->id == AOCS_DET_MEKF) {
            aocs_mekf_t *const f = &det->states.mekf;
            aocs_mekf_output_t mo;
            /* the rate the filter last gave (from the gyro now excluded): the dynamics' starting point */
            aocs_vec3_t w0 = aocs_vec3_zero();
            if (aocs_mekf_get_output(f, &mo) == AOCS_OK) {
                w0 = mo.w_BN_B_hat;
            }
            st = aocs_mekf_set_gyroless(f, inertia_B_kgm2, w0);
        }
    }
    return st;
}

uint32_t aocs_det_is_gyroless(const aocs_det_t *det)
{
    return ((det != NULL) && (det->id == AOCS_DET_MEKF)) ? aocs_mekf_is_gyroless(&det->states.mekf) : 0u;
}

void aocs_det_set_torque(aocs_det_t *det, aocs_vec3_t tau_B_Nm, aocs_vec3_t h_wheels_B_Nms)
{
    if ((det != NULL) && (det->id == AOCS_DET_MEKF)) {
        aocs_mekf_set_torque(&det->states.mekf, tau_B_Nm, h_wheels_B_Nms);
    }
}

void aocs_det_set_st_noise_scale(aocs_det_t *det, real_t scale)
{
    if ((det != NULL) && (det->id == AOCS_DET_MEKF)) {
        aocs_mekf_set_st_noise_scale(&det->states.mekf, scale);
    }
}
