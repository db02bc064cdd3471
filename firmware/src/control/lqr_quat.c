/* lqr_quat: SPEC 2.5, see lqr_quat.h. */
#include <stddef.h>

#include "aocs/control/lqr_quat.h"
#include "aocs/control/gain_matrix.h"

/* set by a successful init only: a zeroed or garbage struct never steps */
#define LQR_QUAT_INIT_MAGIC 0x4C51

aocs_status_t aocs_lqr_quat_init(aocs_lqr_quat_t *law, const aocs_lqr_quat_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (law != NULL) {
        law->initialised = 0;
    }
    if ((law == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        /* a stabilising K of the double-integrator-like model has positive
         * proportional and derivative diagonals */
        st = aocs_gain_matrix_check(cfg->k, AOCS_GAIN_MATRIX_POS_DIAGS);
        if (st == AOCS_OK) {
            law->cfg = *cfg;
            law->initialised = LQR_QUAT_INIT_MAGIC;
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
    } else if (law->initialised != LQR_QUAT_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        st = aocs_att_input_check(in);
    }
    if (st == AOCS_OK) {
        aocs_quat_t qe;
        st = aocs_quat_normalize(aocs_quat_error(in->q_BN, in->qd_DN), &qe);
        if (st == AOCS_OK) {
            const aocs_lqr_quat_config_t *c = &law->cfg;
            real_t x[6];
            /* SPEC 2.5: x = [sign(qe4) qe_vec; we], u = -K x */
            real_t s = aocs_quat_sign_q4(qe);
            for (int i = 0; i < 3; ++i) {
                x[i] = s * qe.q[i];
                x[3 + i] = in->w_BN_B.v[i] - in->wd_B.v[i];
            }
            u = aocs_gain_matrix_mul(c->k, x, AOCS_R(-1.0));
        }
    }
    return aocs_law_set_output(st, u, u_out);
}
