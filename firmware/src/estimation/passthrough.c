/*
 * Estimator PASSTHROUGH (aocs/estimation/determination.h): the measured
 * attitude and rate as they are (the sensor adapter's q_BN and w_BN_B), the
 * input acceptance's verdict as the status. It keeps no estimate.
 */
#include <stddef.h>

#include "aocs/executive.h"

aocs_status_t aocs_det_passthrough_init(aocs_det_passthrough_state_t *s, const aocs_det_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if ((s == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        s->steps = 0u;
    }
    return st;
}

aocs_status_t aocs_det_passthrough_step(aocs_det_passthrough_state_t *s, const aocs_exec_input_t *in,
                                        aocs_status_t accept_status, real_t dt_s, aocs_det_output_t *out)
{
    (void)dt_s; /* nothing is propagated */
    if (s->steps < UINT32_MAX) {
        s->steps += 1u;
    }
    out->q_BN = in->q_BN;
    out->w_BN_B = in->w_BN_B;
    out->valid = in->valid & (AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE);
    out->status = accept_status;
    return accept_status;
}
