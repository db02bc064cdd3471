/* crp_linear: SPEC 2.1, Rotea, Tsiotras, Corless 1998. */
#include <stddef.h>

#include "aocs/control/crp_linear.h"

/* marks a successful init; a zeroed or garbage struct is very unlikely to hold it */
#define CRP_LINEAR_INIT_MAGIC 0x4352

aocs_status_t aocs_crp_linear_init(aocs_crp_linear_t *law, const aocs_crp_linear_config_t *cfg)
{
    aocs_status_t st = AOCS_ERR_NULL_ARG;
    if ((law != NULL) && (cfg != NULL)) {
        st = aocs_law_check_gains(cfg->k1, cfg->k2); /* SPEC 2.1: k1, k2 > 0 */
    }
    if (law != NULL) {
        if (st == AOCS_OK) {
            law->cfg = *cfg;
            law->initialised = CRP_LINEAR_INIT_MAGIC;
        } else {
            law->initialised = 0;
        }
    }
    return st;
}

aocs_status_t aocs_crp_linear_step(aocs_crp_linear_t *law, const aocs_att_input_t *in,
                                   aocs_vec3_t *u_out)
{
    aocs_status_t st = AOCS_OK;
    aocs_vec3_t u = aocs_vec3_zero();

    if ((law == NULL) || (in == NULL) || (u_out == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (law->initialised != CRP_LINEAR_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        st = aocs_att_input_check(in);
    }

    if (st == AOCS_OK) {
        aocs_quat_t qe = aocs_quat_error(in->q_BN, in->qd_DN);
        aocs_vec3_t we = aocs_vec3_sub(in->w_BN_B, in->wd_B);
        aocs_vec3_t rho = aocs_vec3_zero();
        /* short-rotation Gibbs vector; SINGULAR at 180 deg (header) */
        st = aocs_quat_to_crp(qe, &rho);
        if (st == AOCS_OK) {
            /* SPEC 2.1: u = -k1 we - k2 rho */
            u = aocs_vec3_add(aocs_vec3_scale(we, -law->cfg.k1),
                              aocs_vec3_scale(rho, -law->cfg.k2));
        }
    }

    return aocs_law_set_output(st, u, u_out);
}
