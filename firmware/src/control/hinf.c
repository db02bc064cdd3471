/* hinf: SPEC 2.6, see hinf.h. */
#include <stddef.h>

#include "aocs/control/hinf.h"
#include "aocs/control/gain_matrix.h"

/* set by a successful init only: a zeroed or garbage struct never steps */
#define HINF_INIT_MAGIC 0x4849

aocs_status_t aocs_hinf_init(aocs_hinf_t *law, const aocs_hinf_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (law != NULL) {
        law->initialised = 0;
    }
    if ((law == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        /* the LMI design fixes no sign pattern; an all-zero K is no design */
        st = aocs_gain_matrix_check(cfg->k, AOCS_GAIN_MATRIX_ANY_NONZERO);
        if (st == AOCS_OK) {
            law->cfg = *cfg;
            law->initialised = HINF_INIT_MAGIC;
        }
    }
    return st;
}

aocs_status_t aocs_hinf_step(aocs_hinf_t *law, const aocs_att_input_t *in, aocs_vec3_t *u_out)
{
    aocs_status_t st = AOCS_OK;
    aocs_vec3_t u = aocs_vec3_zero();

    if ((law == NULL) || (u_out == NULL) || (in == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (law->initialised != HINF_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        st = aocs_att_input_check(in);
    }
    if (st == AOCS_OK) {
        aocs_quat_t qe;
        st = aocs_quat_normalize(aocs_quat_error(in->q_BN, in->qd_DN), &qe);
        if (st == AOCS_OK) {
            const aocs_hinf_config_t *c = &law->cfg;
            aocs_euler321_t e = aocs_quat_to_euler321(qe);
            aocs_vec3_t we = aocs_vec3_sub(in->w_BN_B, in->wd_B);
            real_t sphi = AOCS_SIN(e.roll);
            real_t cphi = AOCS_COS(e.roll);
            real_t cth = AOCS_COS(e.pitch);
            real_t sth = AOCS_SIN(e.pitch);
            real_t x[6];
            real_t qs_rc = (we.v[1] * sphi) + (we.v[2] * cphi);
            if (cth < AOCS_HINF_COS_PITCH_MIN) {
                cth = AOCS_HINF_COS_PITCH_MIN; /* gimbal lock guard, hinf.h */
            }
            /* SPEC 2.6 state; exact 3-2-1 Euler-rate kinematics (hinf.h) */
            x[0] = e.roll;
            x[1] = e.pitch;
            x[2] = e.yaw;
            x[3] = we.v[0] + ((qs_rc * sth) / cth);
            x[4] = (we.v[1] * cphi) - (we.v[2] * sphi);
            x[5] = qs_rc / cth;
            u = aocs_gain_matrix_mul(c->k, x, AOCS_R(1.0)); /* SPEC 2.6: u = +K x */
        }
    }
    return aocs_law_set_output(st, u, u_out);
}
