/* lqr_quat_i: SPEC 5.2, see lqr_quat_i.h. */
#include <stddef.h>

#include "aocs/control/lqr_quat_i.h"
#include "aocs/control/gain_matrix.h"
#include "aocs/control/integral.h"

/* set by a successful init only: a zeroed or garbage struct never steps */
#define LQR_QUAT_I_INIT_MAGIC 0x4C49

aocs_status_t aocs_lqr_quat_i_init(aocs_lqr_quat_i_t *law, const aocs_lqr_quat_i_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (law != NULL) {
        law->initialised = 0;
        law->z = aocs_vec3_zero();
    }
    if ((law == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        /* every block diagonal (z, qe_vec, we) of a stabilising K of this model is positive */
        st = aocs_gain_matrix9_check(cfg->k, AOCS_GAIN_MATRIX_POS_DIAGS);
        if (st == AOCS_OK) {
            if (!AOCS_IS_FINITE(cfg->z_max)) {
                st = AOCS_ERR_PARAM_NOT_FINITE;
            } else if (!(cfg->z_max > AOCS_R(0.0))) {
                st = AOCS_ERR_INTEGRAL_LIMIT_NOT_POSITIVE;
            } else {
                law->cfg = *cfg;
                law->initialised = LQR_QUAT_I_INIT_MAGIC;
            }
        }
    }
    return st;
}

aocs_status_t aocs_lqr_quat_i_step(aocs_lqr_quat_i_t *law, const aocs_att_input_t *in, aocs_vec3_t *u_out)
{
    aocs_status_t st = AOCS_OK;
    aocs_vec3_t u = aocs_vec3_zero();

    if ((law == NULL) || (u_out == NULL) || (in == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (law->initialised != LQR_QUAT_I_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        st = aocs_att_input_check(in);
    }
    if (st == AOCS_OK) {
        aocs_quat_t qe;
        st = aocs_quat_normalize(aocs_quat_error(in->q_BN, in->qd_DN), &qe);
        if (st == AOCS_OK) {
            const aocs_lqr_quat_i_config_t *c = &law->cfg;
            real_t x[9];
            aocs_vec3_t e;
            aocs_mat3_t sens;
            /* SPEC 5.2: x = [z; s qe_vec; we], u = -K x */
            real_t s = aocs_quat_sign_q4(qe);
            for (int i = 0; i < 3; ++i) {
                x[i] = law->z.v[i];
                x[3 + i] = s * qe.q[i];
                x[6 + i] = in->w_BN_B.v[i] - in->wd_B.v[i];
            }
            u = aocs_gain_matrix9_mul(c->k, x, AOCS_R(-1.0));
            e = aocs_vec3_make(x[3], x[4], x[5]);
            for (int i = 0; i < 3; ++i) {
                for (int j = 0; j < 3; ++j) {
                    sens.m[i][j] = -c->k[i][j]; /* du/dz = -K_z */
                }
            }
            if (aocs_vec3_is_finite(u) != 0) {
                law->z = aocs_integral_update(law->z, e, in->dt_s, sens, u, in->u_max_axis, in->u_max_norm,
                                              c->z_max);
            }
        }
    }
    return aocs_law_set_output(st, u, u_out);
}
