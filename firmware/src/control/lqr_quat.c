/* lqr_quat: SPEC 2.5, see lqr_quat.h. */
#include <stddef.h>

#include "aocs/control/lqr_quat.h"

aocs_status_t aocs_lqr_quat_init(aocs_lqr_quat_t *law, const aocs_lqr_quat_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (law != NULL) {
        law->initialised = 0;
    }
    if ((law == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 6; ++j) {
                if (!AOCS_IS_FINITE(cfg->k[i][j])) {
                    st = AOCS_ERR_PARAM_NOT_FINITE;
                }
            }
        }
        if (st == AOCS_OK) {
            for (int i = 0; i < 3; ++i) {
                /* a stabilising K of the double-integrator-like model has
                 * positive proportional and derivative diagonals */
                if ((!(cfg->k[i][i] > AOCS_R(0.0))) || (!(cfg->k[i][3 + i] > AOCS_R(0.0)))) {
                    st = AOCS_ERR_GAIN_TABLE_INVALID;
                }
            }
        }
        if (st == AOCS_OK) {
            law->cfg = *cfg;
            law->initialised = 1;
        }
    }
    return st;
}

aocs_status_t aocs_lqr_quat_step(aocs_lqr_quat_t *law, const aocs_att_input_t *in, aocs_vec3_t *u_out)
{
    aocs_status_t st = AOCS_OK;
    aocs_vec3_t u = aocs_vec3_zero();

    if ((law == NULL) || (u_out == NULL) || (in == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (law->initialised == 0) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        st = aocs_att_input_check(in);
    }
    if (st == AOCS_OK) {
        aocs_quat_t qe;
        st = aocs_quat_normalize(aocs_quat_error(in->q_BN, in->qd_DN), &qe);
        if (st == AOCS_OK) {
            real_t x[6];
            /* SPEC 2.5: x = [sign(qe4) qe_vec; we] */
            real_t s = aocs_quat_sign_q4(qe);
            for (int i = 0; i < 3; ++i) {
                x[i] = s * qe.q[i];
                x[3 + i] = in->w_BN_B.v[i] - in->wd_B.v[i];
            }
            for (int i = 0; i < 3; ++i) {
                real_t acc = AOCS_R(0.0);
                for (int j = 0; j < 6; ++j) {
                    acc += law->cfg.k[i][j] * x[j];
                }
                u.v[i] = -acc;
            }
            if (aocs_vec3_is_finite(u) == 0) {
                st = AOCS_ERR_OUTPUT_NOT_FINITE; /* finite inputs, overflowing result */
            }
        }
    }
    if (u_out != NULL) {
        *u_out = (st == AOCS_OK) ? u : aocs_vec3_zero();
    }
    return st;
}
