/* quat_nlpd: SPEC 2.3. */
#include <stddef.h>

#include "aocs/control/quat_nlpd.h"

/* marks a successful init; a zeroed or garbage struct is very unlikely to hold it */
#define QUAT_NLPD_INIT_MAGIC 0x4E4C

aocs_status_t aocs_quat_nlpd_init(aocs_quat_nlpd_t *law, const aocs_quat_nlpd_config_t *cfg)
{
    aocs_status_t st = AOCS_ERR_NULL_ARG;
    if ((law != NULL) && (cfg != NULL)) {
        st = aocs_law_check_gains(cfg->kp, cfg->kd); /* SPEC 2.3: kp, kd > 0 */
        if ((st == AOCS_OK) && (cfg->variant != AOCS_QUAT_NLPD_NEG) && (cfg->variant != AOCS_QUAT_NLPD_POS)) {
            st = AOCS_ERR_MODE_INVALID;
        }
    }
    if (law != NULL) {
        if (st == AOCS_OK) {
            law->cfg = *cfg;
            law->initialised = QUAT_NLPD_INIT_MAGIC;
        } else {
            law->initialised = 0;
        }
    }
    return st;
}

aocs_status_t aocs_quat_nlpd_step(aocs_quat_nlpd_t *law, const aocs_att_input_t *in,
                                  aocs_vec3_t *u_out)
{
    aocs_status_t st = AOCS_OK;
    aocs_vec3_t u = aocs_vec3_zero();

    if ((law == NULL) || (in == NULL) || (u_out == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (law->initialised != QUAT_NLPD_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        st = aocs_att_input_check(in);
    }

    if (st == AOCS_OK) {
        aocs_quat_t qe = aocs_quat_error(in->q_BN, in->qd_DN);
        aocs_vec3_t qe_vec = aocs_quat_vec(qe);
        aocs_vec3_t we = aocs_vec3_sub(in->w_BN_B, in->wd_B);
        real_t sgn = aocs_quat_sign_q4(qe);
        real_t qq = aocs_vec3_norm_sq(qe_vec);
        /* SPEC 2.3: rate gain kd (1 - qq) for NEG, kd (1 + qq) for POS */
        real_t rate_factor = (law->cfg.variant == AOCS_QUAT_NLPD_NEG) ? (AOCS_R(1.0) - qq)
                                                                      : (AOCS_R(1.0) + qq);
        u = aocs_vec3_add(aocs_vec3_scale(qe_vec, -law->cfg.kp * sgn),
                          aocs_vec3_scale(we, -law->cfg.kd * rate_factor));
    }

    return aocs_law_set_output(st, u, u_out);
}
