/*
 * The executive's reaction wheel hook (executive.h "Reaction wheels"): the
 * one place where the executive meets the wheel array (wheel_array.h).
 */
#include <stddef.h>

#include "exec_internal.h"

aocs_status_t aocs_exec_wheels_init(aocs_exec_t *exec, const aocs_exec_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (cfg->wheels.n != 0u) {
        aocs_wheels_config_t w = cfg->wheels;
        w.period_s = cfg->period_s; /* the speed protection's horizon is the control period */
        st = aocs_wheels_init(&exec->wheels, &w);
    }
    return st;
}

void aocs_exec_wheels_apply(aocs_exec_t *exec, const real_t *omega_radps, aocs_vec3_t w_BN_B,
                            aocs_exec_output_t *out, int *saturated)
{
    if (exec->wheels.initialised != 0) {
        out->wheels_status = aocs_wheels_allocate(&exec->wheels, out->u_cmd, omega_radps, &out->wheels);
        if (exec->mode == AOCS_EXEC_MODE_STANDBY) {
            /* STANDBY commands nothing: no motor torque at all, so neither the friction feedforward nor the
             * null-space management (they act while a law or the safe damping flies; docs/spec.md 5.3.2) */
            for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
                out->wheels.u_s_nm[i] = AOCS_R(0.0);
                out->wheels.friction_nm[i] = AOCS_R(0.0);
                out->wheels.null_nm[i] = AOCS_R(0.0);
            }
        }
        /* what the wheels deliver: u_cmd scaled (same direction), zero when the allocation failed */
        out->u_cmd = out->wheels.u_body_B_nm;
        if ((out->wheels_status != AOCS_OK) || (out->wheels.scale < AOCS_R(1.0))) {
            *saturated = 1;
        }
        if (aocs_vec3_is_finite(w_BN_B) != 0) {
            (void)aocs_wheels_momentum(&exec->wheels, w_BN_B, omega_radps, &out->momentum);
        }
        /* kept for step_no_input (which passes these same arrays back: copying onto itself is a no-op) */
        for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
            exec->wheel_speed_last[i] = omega_radps[i];
        }
        exec->w_last_B = w_BN_B;
    }
}
