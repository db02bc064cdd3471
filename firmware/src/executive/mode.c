/*
 * The executive's mode helpers: the saturating event counter, the target
 * check, and the SAFE mode: its configuration check and its command (rate
 * damping on the estimate).
 */
#include <stddef.h>

#include "exec_internal.h"

void aocs_exec_count(uint32_t *counter, uint32_t n)
{
    if (counter != NULL) {
        if ((UINT32_MAX - *counter) < n) {
            *counter = UINT32_MAX;
        } else {
            *counter += n;
        }
    }
}

static int quat_is_unit(aocs_quat_t q)
{
    real_t n = aocs_quat_norm(q);
    return (AOCS_IS_FINITE(n) && (AOCS_FABS(n - AOCS_R(1.0)) <= AOCS_QUAT_UNIT_TOL)) ? 1 : 0;
}

aocs_status_t aocs_exec_target_check(const aocs_exec_target_t *target)
{
    aocs_status_t st = AOCS_OK;
    if (target == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if ((aocs_quat_is_finite(target->qd_DN) == 0) || (quat_is_unit(target->qd_DN) == 0) ||
               (aocs_vec3_is_finite(target->wd_B) == 0) || (aocs_vec3_is_finite(target->wd_dot_B) == 0)) {
        st = AOCS_ERR_TARGET_INVALID;
    } else {
        st = AOCS_OK;
    }
    return st;
}

aocs_vec3_t aocs_exec_safe_command(const aocs_exec_config_t *cfg, aocs_law_id_t law,
                                   const aocs_det_output_t *est)
{
    aocs_vec3_t u = aocs_vec3_zero();
    /* orbit: zero force (drifting is safe, thrusting on bad data is not) */
    if ((cfg != NULL) && (est != NULL) && (aocs_law_is_orbit(law) == 0) &&
        ((est->valid & AOCS_EXEC_VALID_RATE) != 0u) && (aocs_vec3_is_finite(est->w_BN_B) != 0)) {
        /* rate damping: d/dt(0.5 w^T J w) = -k_safe |w|^2 <= 0 without attitude knowledge */
        u = aocs_vec3_scale(est->w_BN_B, -cfg->k_safe);
    }
    return u;
}


aocs_status_t aocs_exec_safe_config_check(const aocs_exec_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (cfg == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (!AOCS_IS_FINITE(cfg->k_safe)) {
        st = AOCS_ERR_PARAM_NOT_FINITE;
    } else if (!(cfg->k_safe > AOCS_R(0.0))) {
        st = AOCS_ERR_GAIN_NOT_POSITIVE;
    } else {
        st = AOCS_OK;
    }
    return st;
}
