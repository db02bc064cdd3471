/* smc: SPEC 2.4, Crassidis, Vadali, Markley 2000. */
#include <stddef.h>

#include "aocs/control/smc.h"

/* marks a successful init; a zeroed or garbage struct is very unlikely to hold it */
#define SMC_INIT_MAGIC 0x534D

static int smc_all_positive(aocs_vec3_t a)
{
    return ((a.v[0] > AOCS_R(0.0)) && (a.v[1] > AOCS_R(0.0)) && (a.v[2] > AOCS_R(0.0))) ? 1 : 0;
}

/* SPEC 2.4: s_i / eps_i inside the layer, sign(s_i) outside (the reference's |s|/eps is a typo) */
static aocs_vec3_t smc_sat(aocs_vec3_t s, aocs_vec3_t eps)
{
    aocs_vec3_t out = aocs_vec3_zero();
    int i;
    for (i = 0; i < 3; ++i) {
        if (AOCS_FABS(s.v[i]) <= eps.v[i]) {
            out.v[i] = s.v[i] / eps.v[i];
        } else if (s.v[i] > AOCS_R(0.0)) {
            out.v[i] = AOCS_R(1.0);
        } else {
            out.v[i] = AOCS_R(-1.0);
        }
    }
    return out;
}

aocs_status_t aocs_smc_init(aocs_smc_t *law, const aocs_smc_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if ((law == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        st = aocs_mat3_check_inertia(cfg->inertia);
        if (st == AOCS_OK) {
            if ((aocs_vec3_is_finite(cfg->lambda) == 0) || (aocs_vec3_is_finite(cfg->g) == 0) ||
                (aocs_vec3_is_finite(cfg->eps) == 0)) {
                st = AOCS_ERR_PARAM_NOT_FINITE;
            } else if ((smc_all_positive(cfg->lambda) == 0) || (smc_all_positive(cfg->g) == 0)) {
                st = AOCS_ERR_GAIN_NOT_POSITIVE;
            } else if (smc_all_positive(cfg->eps) == 0) {
                st = AOCS_ERR_BOUNDARY_LAYER_NOT_POSITIVE;
            } else {
                st = AOCS_OK;
            }
        }
    }
    if (law != NULL) {
        if (st == AOCS_OK) {
            law->cfg = *cfg;
            law->initialised = SMC_INIT_MAGIC;
        } else {
            law->initialised = 0;
        }
    }
    return st;
}

aocs_status_t aocs_smc_step(aocs_smc_t *law, const aocs_att_input_t *in, aocs_vec3_t *u_out)
{
    aocs_status_t st = AOCS_OK;
    aocs_vec3_t u = aocs_vec3_zero();

    if ((law == NULL) || (in == NULL) || (u_out == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (law->initialised != SMC_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        st = aocs_att_input_check(in);
    }

    if (st == AOCS_OK) {
        const aocs_smc_config_t *c = &law->cfg;
        aocs_quat_t qe = aocs_quat_error(in->q_BN, in->qd_DN);
        aocs_vec3_t qe_vec = aocs_quat_vec(qe);
        aocs_vec3_t we = aocs_vec3_sub(in->w_BN_B, in->wd_B);
        real_t sgn = aocs_quat_sign_q4(qe);
        /* sliding surface s = we + Lambda sign(qe4) qe_vec */
        aocs_vec3_t s = aocs_vec3_add(we, aocs_vec3_scale(aocs_vec3_hadamard(c->lambda, qe_vec), sgn));
        /* d/dt(qe_vec) = 0.5 (qe4 I + qe_vec^x) we */
        aocs_vec3_t qe_vec_dot = aocs_vec3_scale(
            aocs_vec3_add(aocs_vec3_scale(we, qe.q[3]), aocs_vec3_cross(qe_vec, we)), AOCS_R(0.5));
        /* J (-Lambda sign(qe4) qe_vec_dot + wd_dot - G sat(s, eps)): one product by J */
        aocs_vec3_t acc = aocs_vec3_sub(
            aocs_vec3_add(aocs_vec3_scale(aocs_vec3_hadamard(c->lambda, qe_vec_dot), -sgn), in->wd_dot_B),
            aocs_vec3_hadamard(c->g, smc_sat(s, c->eps)));
        aocs_vec3_t h = aocs_mat3_mul_vec(c->inertia, in->w_BN_B);
        /* + w x (J w) cancels the gyroscopic term of the plant */
        u = aocs_vec3_add(aocs_mat3_mul_vec(c->inertia, acc), aocs_vec3_cross(in->w_BN_B, h));
    }

    return aocs_law_set_output(st, u, u_out);
}
