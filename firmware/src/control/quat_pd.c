/* quat_pd: SPEC 2.2. */
#include <stddef.h>

#include "aocs/control/quat_pd.h"

/* marks a successful init; a zeroed or garbage struct is very unlikely to hold it */
#define QUAT_PD_INIT_MAGIC 0x5144

aocs_status_t aocs_quat_pd_init(aocs_quat_pd_t *law, const aocs_quat_pd_config_t *cfg)
{
    aocs_status_t st = AOCS_ERR_NULL_ARG;
    if ((law != NULL) && (cfg != NULL)) {
        st = aocs_law_check_gains(cfg->kp, cfg->kd); /* SPEC 2.2: kp, kd > 0 */
    }
    if (law != NULL) {
        if (st == AOCS_OK) {
            law->cfg = *cfg;
            law->initialised = QUAT_PD_INIT_MAGIC;
        } else {
            law->initialised = 0;
        }
    }
    return st;
}

aocs_status_t aocs_quat_pd_step(aocs_quat_pd_t *law, const aocs_att_input_t *in, aocs_vec3_t *u_out)
{
    aocs_status_t st = AOCS_OK;
    aocs_vec3_t u = aocs_vec3_zero();

    if ((law == NULL) || (in == NULL) || (u_out == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (law->initialised != QUAT_PD_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        st = aocs_att_input_check(in);
    }

    if (st == AOCS_OK) {
        aocs_quat_t qe = aocs_quat_error(in->q_BN, in->qd_DN);
        aocs_vec3_t we = aocs_vec3_sub(in->w_BN_B, in->wd_B);
        real_t sgn = aocs_quat_sign_q4(qe);
        /* SPEC 2.2: u = -kp sign(qe4) qe_vec - kd we */
        u = aocs_vec3_add(aocs_vec3_scale(aocs_quat_vec(qe), -law->cfg.kp * sgn),
                          aocs_vec3_scale(we, -law->cfg.kd));
    }

    return aocs_law_set_output(st, u, u_out);
}
