/* mrp_sat: SPEC 2.7, Gao, Lu, Wang 2010; see mrp_sat.h for the bound proof. */
#include <stddef.h>

#include "aocs/control/mrp_sat.h"
#include "aocs/control/saturate.h"

/* set by a successful init only: a zeroed or garbage struct never steps */
#define MRP_SAT_INIT_MAGIC 0x4D53

/* 2 / sqrt 3, the factor of the chain M2 <= (2/sqrt 3) uM (mrp_sat.h) */
#define MRP_SAT_TWO_OVER_SQRT3 AOCS_R(1.1547005383792515290)

static int mrp_sat_all_finite(const aocs_mrp_sat_config_t *cfg)
{
    int ok = 1;
    if ((!AOCS_IS_FINITE(cfg->k)) || (!AOCS_IS_FINITE(cfg->lambda)) || (!AOCS_IS_FINITE(cfg->u_max))) {
        ok = 0;
    } else if ((aocs_vec3_is_finite(cfg->l1) == 0) || (aocs_vec3_is_finite(cfg->m1) == 0) ||
               (aocs_vec3_is_finite(cfg->l2) == 0) || (aocs_vec3_is_finite(cfg->m2) == 0)) {
        ok = 0;
    } else {
        ok = 1;
    }
    return ok;
}

/* the linear-variant inequality chain of mrp_sat.h, one code per violation */
static aocs_status_t mrp_sat_check_chain(const aocs_mrp_sat_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    const real_t m2_max = MRP_SAT_TWO_OVER_SQRT3 * cfg->u_max;
    const real_t m2_tol = AOCS_R(1.0) + (AOCS_R(8.0) * AOCS_REAL_EPS);
    const real_t eq_tol = AOCS_R(4.0) * AOCS_REAL_EPS;

    for (int i = 0; (i < 3) && (st == AOCS_OK); ++i) {
        if (!(cfg->l1.v[i] > AOCS_R(0.0)) || !(cfg->m1.v[i] > AOCS_R(0.0)) ||
            !(cfg->l2.v[i] > AOCS_R(0.0)) || !(cfg->m2.v[i] > AOCS_R(0.0))) {
            st = AOCS_ERR_SAT_LIMIT_NOT_POSITIVE;
        }
    }
    for (int i = 0; (i < 3) && (st == AOCS_OK); ++i) {
        real_t l1 = cfg->l1.v[i];
        real_t m1 = cfg->m1.v[i];
        real_t scale = (l1 > m1) ? l1 : m1;
        if (AOCS_FABS(l1 - m1) > (eq_tol * scale)) {
            st = AOCS_ERR_SAT_L1_NOT_EQUAL_M1;
        } else if (!(m1 < cfg->l2.v[i])) {
            st = AOCS_ERR_SAT_M1_NOT_BELOW_L2;
        } else if (!(cfg->l2.v[i] <= cfg->m2.v[i])) {
            st = AOCS_ERR_SAT_L2_ABOVE_M2;
        } else if (!(cfg->m2.v[i] <= (m2_max * m2_tol))) {
            st = AOCS_ERR_SAT_M2_ABOVE_UMAX;
        } else {
            st = AOCS_OK;
        }
    }
    return st;
}

aocs_status_t aocs_mrp_sat_init(aocs_mrp_sat_t *law, const aocs_mrp_sat_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (law != NULL) {
        law->initialised = 0;
        law->shadow_used = 0;
        law->guard_count = 0U;
    }
    if ((law == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if ((cfg->variant != AOCS_MRP_SAT_LINEAR) && (cfg->variant != AOCS_MRP_SAT_TANH)) {
        st = AOCS_ERR_MODE_INVALID;
    } else if (mrp_sat_all_finite(cfg) == 0) {
        st = AOCS_ERR_PARAM_NOT_FINITE;
    } else if (!(cfg->k > AOCS_R(0.0)) || !(cfg->lambda > AOCS_R(0.0))) {
        st = AOCS_ERR_GAIN_NOT_POSITIVE;
    } else if (!(cfg->u_max > AOCS_R(0.0))) {
        st = AOCS_ERR_SAT_LIMIT_NOT_POSITIVE;
    } else if (cfg->variant == AOCS_MRP_SAT_LINEAR) {
        st = mrp_sat_check_chain(cfg);
    } else {
        st = AOCS_OK;
    }
    if (st == AOCS_OK) {
        law->cfg = *cfg;
        law->initialised = MRP_SAT_INIT_MAGIC;
    }
    return st;
}

aocs_status_t aocs_mrp_sat_step(aocs_mrp_sat_t *law, const aocs_att_input_t *in, aocs_vec3_t *u_out)
{
    aocs_status_t st = AOCS_OK;
    aocs_vec3_t u = aocs_vec3_zero();
    aocs_vec3_t we = aocs_vec3_zero();

    if ((law == NULL) || (u_out == NULL) || (in == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (law->initialised != MRP_SAT_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        st = aocs_att_input_check(in);
    }
    if (st == AOCS_OK) {
        we = aocs_vec3_sub(in->w_BN_B, in->wd_B);
        if (aocs_vec3_is_finite(we) == 0) {
            st = AOCS_ERR_OUTPUT_NOT_FINITE; /* finite w, wd: w - wd overflowed */
        }
    }
    if (st == AOCS_OK) {
        aocs_quat_t qe;
        st = aocs_quat_normalize(aocs_quat_error(in->q_BN, in->qd_DN), &qe);
        if (st == AOCS_OK) {
            const aocs_mrp_sat_config_t *c = &law->cfg;
            /* |sigma| <= 1: shadow set when qe4 < 0 (SPEC 1) */
            aocs_vec3_t sigma = aocs_quat_to_mrp(qe);
            aocs_mat3_t g = aocs_mrp_b_matrix(sigma);
            aocs_vec3_t sigma_dot = aocs_mat3_mul_vec(g, we);
            aocs_vec3_t y;
            int guard = 0;

            if (qe.q[3] < AOCS_R(0.0)) {
                law->shadow_used = 1;
            } else {
                law->shadow_used = 0;
            }
            if (c->variant == AOCS_MRP_SAT_LINEAR) {
                /* u = G^T S2(-k sigmadot - S1(lambda sigma)) */
                for (int i = 0; i < 3; ++i) {
                    real_t s1 = aocs_sat_linear(c->lambda * sigma.v[i], c->l1.v[i], c->m1.v[i]);
                    real_t arg = (-(c->k * sigma_dot.v[i])) - s1;
                    y.v[i] = aocs_sat_linear(arg, c->l2.v[i], c->m2.v[i]);
                }
                u = aocs_mat3_tmul_vec(g, y);
            } else {
                /* u = -(2/sqrt 3) G^T S3(k sigmadot + lambda sigma) */
                for (int i = 0; i < 3; ++i) {
                    real_t arg = (c->k * sigma_dot.v[i]) + (c->lambda * sigma.v[i]);
                    y.v[i] = aocs_sat_tanh(arg, c->u_max);
                }
                u = aocs_vec3_scale(aocs_mat3_tmul_vec(g, y), -MRP_SAT_TWO_OVER_SQRT3);
            }
            if (aocs_vec3_is_finite(u) == 0) {
                st = AOCS_ERR_OUTPUT_NOT_FINITE; /* finite inputs, overflowing result */
            } else {
                /* exact-arithmetic no-op (mrp_sat.h); absorbs rounding */
                u = aocs_sat_scale_to_norm(u, c->u_max, &guard);
                if (guard != 0) {
                    if (law->guard_count < UINT32_MAX) {
                        law->guard_count += 1U;
                    }
                }
            }
        }
    }
    return aocs_law_set_output(st, u, u_out);
}
