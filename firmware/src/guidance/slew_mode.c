/*
 * Guidance mode SLEW (aocs/guidance/guidance.h, guidance_modes.def;
 * docs/spec.md "Slew guidance"): a commanded target starts a rest-to-rest
 * eigenaxis slew (slew.c) from the attitude of the next usable sample, and
 * the law tracks the profile's qd(t), wd_B(t), wd_dot_B(t).
 */
#include <stddef.h>

#include "aocs/executive.h"

aocs_status_t aocs_guidance_slew_check(const aocs_exec_guidance_config_t *gcfg, const aocs_exec_target_t *target,
                                       aocs_vec3_t rate_D)
{
    aocs_status_t st = AOCS_OK;
    if ((aocs_guidance_vec_nonzero(rate_D) != 0) || (aocs_guidance_vec_nonzero(target->wd_B) != 0) ||
        (aocs_guidance_vec_nonzero(target->wd_dot_B) != 0)) {
        st = AOCS_ERR_GUIDANCE_TARGET_MOVING; /* a slew needs a fixed target */
    } else {
        st = aocs_slew_config_check(&gcfg->slew);
    }
    return st;
}

void aocs_guidance_slew_step(aocs_guidance_t *g, const aocs_guidance_input_t *in, aocs_exec_target_t *target)
{
    if ((g->slew_pending != 0) && (in->usable != 0) && (in->law_active != 0)) {
        aocs_slew_envelope_t env;
        env.u_max_axis_Nm = g->u_max_axis;
        env.u_max_norm_Nm = g->u_max_norm;
        env.wheels = in->wheels;
        /* config, limits and target were validated: a failure leaves a zero-length slew at the target */
        (void)aocs_slew_plan(&g->slew, &g->cfg.slew, &env, in->est->q_BN, g->target.qd_DN);
        g->slew_t0_ns = in->t_ns;
        g->slew_pending = 0;
        g->scaled = 0; /* a new plan runs on its own clock */
    }
    if (g->slew_pending == 0) {
        aocs_slew_ref_t ref;
        if (g->scaled != 0) {
            /* the slowed profile (aocs_guidance_slow_down): rates times k, accelerations times k^2 */
            const real_t k = g->time_scale;
            aocs_slew_eval(&g->slew, aocs_guidance_profile_time_s(g, in->t_ns), &ref);
            ref.wd_D = aocs_vec3_scale(ref.wd_D, k);
            ref.wd_dot_D = aocs_vec3_scale(ref.wd_dot_D, k * k);
            ref.theta_dot_radps *= k;
            ref.theta_ddot_radps2 *= k * k;
        } else {
            aocs_slew_eval(&g->slew, aocs_guidance_elapsed_s(in->t_ns, g->slew_t0_ns), &ref);
        }
        target->qd_DN = ref.qd_DN;
        target->wd_B = aocs_vec3_zero();
        target->wd_dot_B = aocs_vec3_zero();
        if (in->usable != 0) {
            aocs_guidance_slew_rates(in->est->q_BN, ref.qd_DN, ref.wd_D, ref.wd_dot_D, in->est->w_BN_B,
                                     &target->wd_B, &target->wd_dot_B);
        }
    }
}
