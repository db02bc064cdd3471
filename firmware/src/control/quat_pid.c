/* quat_pid: SPEC 5.2, see quat_pid.h. */
#include <stddef.h>

#include "aocs/control/quat_pid.h"
#include "aocs/control/integral.h"

/* marks a successful init; a zeroed or garbage struct is very unlikely to hold it */
#define QUAT_PID_INIT_MAGIC 0x5149

real_t aocs_quat_pid_inertia_bound(aocs_mat3_t j)
{
    real_t bound = AOCS_R(0.0);
    for (int i = 0; i < 3; ++i) {
        real_t row = AOCS_FABS(j.m[i][0]) + AOCS_FABS(j.m[i][1]) + AOCS_FABS(j.m[i][2]);
        bound = (row > bound) ? row : bound;
    }
    return bound;
}

static aocs_status_t quat_pid_check(const aocs_quat_pid_config_t *cfg)
{
    aocs_status_t st = aocs_law_check_gains(cfg->kp, cfg->kd);
    if (st == AOCS_OK) {
        st = aocs_law_check_gains(cfg->ki, cfg->z_max);
        if ((st == AOCS_ERR_GAIN_NOT_POSITIVE) && (cfg->ki > AOCS_R(0.0))) {
            st = AOCS_ERR_INTEGRAL_LIMIT_NOT_POSITIVE; /* ki > 0, so z_max <= 0 */
        }
    }
    if (st == AOCS_OK) {
        st = aocs_mat3_check_inertia(cfg->inertia);
    }
    if (st == AOCS_OK) {
        /* quat_pid.h: Routh on lambda s^3 + kd s^2 + (kp/2) s + ki/2 for every principal axis */
        const real_t lambda_max = aocs_quat_pid_inertia_bound(cfg->inertia);
        if (!((cfg->kd * cfg->kp) > (lambda_max * cfg->ki))) {
            st = AOCS_ERR_PID_NOT_HURWITZ;
        }
    }
    return st;
}

aocs_status_t aocs_quat_pid_init(aocs_quat_pid_t *law, const aocs_quat_pid_config_t *cfg)
{
    aocs_status_t st = AOCS_ERR_NULL_ARG;
    if ((law != NULL) && (cfg != NULL)) {
        st = quat_pid_check(cfg);
    }
    if (law != NULL) {
        law->z = aocs_vec3_zero();
        if (st == AOCS_OK) {
            law->cfg = *cfg;
            law->initialised = QUAT_PID_INIT_MAGIC;
        } else {
            law->initialised = 0;
        }
    }
    return st;
}

aocs_status_t aocs_quat_pid_step(aocs_quat_pid_t *law, const aocs_att_input_t *in, aocs_vec3_t *u_out)
{
    aocs_status_t st = AOCS_OK;
    aocs_vec3_t u = aocs_vec3_zero();

    if ((law == NULL) || (in == NULL) || (u_out == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (law->initialised != QUAT_PID_INIT_MAGIC) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        st = aocs_att_input_check(in);
    }

    if (st == AOCS_OK) {
        const aocs_quat_pid_config_t *c = &law->cfg;
        aocs_quat_t qe = aocs_quat_error(in->q_BN, in->qd_DN);
        aocs_vec3_t we = aocs_vec3_sub(in->w_BN_B, in->wd_B);
        /* SPEC 5.2: e = s qe_vec, s = sign(qe4) */
        aocs_vec3_t e = aocs_vec3_scale(aocs_quat_vec(qe), aocs_quat_sign_q4(qe));
        /* SPEC 5.2: u = -kp e - kd we - ki z */
        u = aocs_vec3_add(aocs_vec3_add(aocs_vec3_scale(e, -c->kp), aocs_vec3_scale(we, -c->kd)),
                          aocs_vec3_scale(law->z, -c->ki));
        if (aocs_vec3_is_finite(u) != 0) {
            /* du/dz = -ki I; z(k+1) = z(k) + dt e unless it grows a saturated command (integral.h) */
            law->z = aocs_integral_update(law->z, e, in->dt_s, aocs_mat3_scale(aocs_mat3_identity(), -c->ki), u,
                                          in->u_max_axis, in->u_max_norm, c->z_max);
        }
    }

    return aocs_law_set_output(st, u, u_out);
}
