/*
 * Common input validation of the control laws (law_io.h), and the gain check
 * and output rule the laws share.
 *
 * Order of the checks, so that every failure has one deterministic code:
 * NULL pointer, then dt (AOCS_ERR_DT_INVALID also when dt is NaN or Inf, as
 * types.h defines that code), then non-finite values in any other field
 * (AOCS_ERR_INPUT_NOT_FINITE), then the unit norm of both quaternions
 * (AOCS_ERR_QUAT_NOT_UNIT). The laws call this before touching any input.
 */
#include <stddef.h>

#include "aocs/control/law_io.h"

/* |q| within AOCS_QUAT_UNIT_TOL of 1; q is already known to be finite */
static int law_io_quat_is_unit(aocs_quat_t q)
{
    real_t n = aocs_quat_norm(q);
    return (AOCS_FABS(n - AOCS_R(1.0)) <= AOCS_QUAT_UNIT_TOL) ? 1 : 0;
}

static aocs_status_t law_io_dt_check(real_t dt_s)
{
    aocs_status_t st = AOCS_OK;
    if (!AOCS_IS_FINITE(dt_s)) {
        st = AOCS_ERR_DT_INVALID;
    } else if (!(dt_s > AOCS_R(0.0))) {
        st = AOCS_ERR_DT_INVALID;
    } else {
        st = AOCS_OK;
    }
    return st;
}

aocs_status_t aocs_att_input_check(const aocs_att_input_t *in)
{
    aocs_status_t st = AOCS_OK;
    if (in == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        st = law_io_dt_check(in->dt_s);
        if (st == AOCS_OK) {
            if ((aocs_quat_is_finite(in->q_BN) == 0) || (aocs_quat_is_finite(in->qd_DN) == 0) ||
                (aocs_vec3_is_finite(in->w_BN_B) == 0) || (aocs_vec3_is_finite(in->wd_B) == 0) ||
                (aocs_vec3_is_finite(in->wd_dot_B) == 0)) {
                st = AOCS_ERR_INPUT_NOT_FINITE;
            } else if ((law_io_quat_is_unit(in->q_BN) == 0) || (law_io_quat_is_unit(in->qd_DN) == 0)) {
                st = AOCS_ERR_QUAT_NOT_UNIT;
            } else {
                st = AOCS_OK;
            }
        }
    }
    return st;
}

aocs_status_t aocs_orbit_input_check(const aocs_orbit_input_t *in)
{
    aocs_status_t st = AOCS_OK;
    if (in == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        st = law_io_dt_check(in->dt_s);
        if ((st == AOCS_OK) &&
            ((aocs_vec3_is_finite(in->vel_mps) == 0) || (aocs_vec3_is_finite(in->pos_m) == 0))) {
            st = AOCS_ERR_INPUT_NOT_FINITE;
        }
    }
    return st;
}

aocs_status_t aocs_law_check_gains(real_t g1, real_t g2)
{
    aocs_status_t st = AOCS_OK;
    if (!AOCS_IS_FINITE(g1) || !AOCS_IS_FINITE(g2)) {
        st = AOCS_ERR_PARAM_NOT_FINITE;
    } else if (!(g1 > AOCS_R(0.0)) || !(g2 > AOCS_R(0.0))) {
        st = AOCS_ERR_GAIN_NOT_POSITIVE;
    } else {
        st = AOCS_OK;
    }
    return st;
}

aocs_status_t aocs_law_set_output(aocs_status_t st, aocs_vec3_t u, aocs_vec3_t *u_out)
{
    aocs_status_t out_st = st;
    if ((out_st == AOCS_OK) && (aocs_vec3_is_finite(u) == 0)) {
        out_st = AOCS_ERR_OUTPUT_NOT_FINITE; /* finite inputs, overflowing result */
    }
    if (u_out != NULL) {
        *u_out = (out_st == AOCS_OK) ? u : aocs_vec3_zero();
    }
    return out_st;
}
