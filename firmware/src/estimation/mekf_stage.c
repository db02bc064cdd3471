/*
 * Estimator MEKF (row of aocs/estimation/determination.def): the adapter
 * between the attitude-determination stage and the filter of mekf.c
 * (docs/spec.md 5.6.11, "The MEKF as the determination stage").
 *
 * In:  the executive's sample (aocs_exec_input_t) and the input acceptance's
 *      verdict on it. The filter is stepped only on an accepted sample that
 *      carries a gyro rate (VALID_GYRO: the acceptance checked it finite and
 *      within range for this row's NEEDS): time t_sensor_ns, rate gyro_w_B,
 *      the star-tracker sample (st_q_SN at st_t_meas_ns) when VALID_ST.
 *      A rejected sample (stale, a tick gap, no gyro) does not move the
 *      filter: its time may not be in order, and it has no rate to hold.
 * Out: the estimate (q_BN_hat, w = gyro - b_hat) with status AOCS_OK once the
 *      filter holds one; else the reason (the acceptance's verdict, or
 *      AOCS_ERR_MEKF_NO_ATTITUDE while waiting for a tracker sample, ...),
 *      with the RATE flag and w = gyro - b_hat whenever this sample's gyro
 *      rate is usable, so the SAFE mode damps the body rate without
 *      attitude knowledge (b_hat: the filter's bias estimate once started,
 *      the configured prior bias0 before). The telemetry: bias, the
 *      covariance's upper triangle, the tracker sample's verdict, counts.
 *      Gyroless (spec 5.6.12, after fault management excluded the gyro): the
 *      filter is stepped on every accepted sample without reading the gyro;
 *      AOCS_ERR_MEKF_GYROLESS_CONVERGING with the RATE flag and the rate
 *      estimate while a rate 1-sigma is above mekf.gyroless_rate_sigma_radps;
 *      the covariance's rows 3..5 are then the rate error's.
 */
#include <stddef.h>

#include "aocs/executive.h"

/* The gyro rate of this sample when usable (flag set, finite, within the filter's range): 1 and *w set. */
static int mekf_stage_gyro(const aocs_exec_input_t *in, aocs_vec3_t *w)
{
    int ok = 0;
    if (((in->valid & AOCS_EXEC_VALID_GYRO) != 0u) && (aocs_vec3_is_finite(in->gyro_w_B) != 0) &&
        (aocs_vec3_norm_inf(in->gyro_w_B) <= AOCS_MEKF_RATE_MAX_RADPS)) {
        *w = in->gyro_w_B;
        ok = 1;
    }
    return ok;
}

/* The bias SAFE subtracts from the gyro: the estimate once the filter started, the prior before. */
static aocs_vec3_t mekf_stage_bias(const aocs_mekf_t *s)
{
    aocs_vec3_t b = s->cfg.bias0_B_radps;
    if (s->started != 0u) {
        b = s->bias_B_hat;
    }
    return b;
}

/* spec 5.6.12: 1 when every rate 1-sigma of the gyroless estimate is at or below sigma_max */
static int mekf_stage_rate_known(const aocs_mekf_output_t *mo, real_t sigma_max)
{
    int known = 1;
    for (int i = 3; i < 6; ++i) {
        if (!(mo->sigma[i] <= sigma_max)) {
            known = 0;
        }
    }
    return known;
}

/*
 * The acceptance took a sample whose time the filter has already passed:
 * the frame acceptance resynchronised to a restarted clock (exec/acceptance.h).
 * The filter starts afresh (its counters kept, one restart more) and takes
 * this sample again, so a tracker sample in it starts the new estimate.
 */
static aocs_status_t mekf_stage_clock_restart(aocs_mekf_t *s, const aocs_mekf_input_t *mi, aocs_mekf_output_t *mo)
{
    const uint32_t n_updates = s->n_updates;
    const uint32_t n_gated = s->n_gated;
    const uint32_t n_hostile = s->n_hostile;
    const uint32_t n_restarts = s->n_restarts;
    aocs_status_t st = aocs_mekf_reset(s);
    if (st == AOCS_OK) {
        s->n_updates = n_updates;
        s->n_gated = n_gated;
        s->n_hostile = n_hostile;
        s->n_restarts = n_restarts;
        if (n_restarts < UINT32_MAX) {
            s->n_restarts += 1u;
        }
        st = aocs_mekf_step(s, mi, mo);
    }
    return st;
}

aocs_status_t aocs_det_mekf_init(aocs_mekf_t *s, const aocs_det_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if ((s == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        st = aocs_mekf_init(s, &cfg->mekf);
    }
    return st;
}

aocs_status_t aocs_det_mekf_step(aocs_mekf_t *s, const aocs_exec_input_t *in, aocs_status_t accept_status,
                                 real_t dt_s, aocs_det_output_t *out)
{
    aocs_status_t st = accept_status;
    aocs_mekf_output_t mo;
    aocs_vec3_t w_gyro = aocs_vec3_zero();
    const uint32_t gyroless = aocs_mekf_is_gyroless(s);
    /* spec 5.6.12: once gyroless the gyro is neither read nor needed */
    const int gyro_ok = (gyroless == 0u) ? mekf_stage_gyro(in, &w_gyro) : 0;
    aocs_vec3_t w_rate = aocs_vec3_zero(); /* the rate SAFE may damp on when the estimate is refused */
    int rate_ok = 0;
    (void)dt_s; /* the filter propagates over the samples' own times */

    if ((accept_status == AOCS_OK) && ((gyro_ok != 0) || (gyroless != 0u))) {
        aocs_mekf_input_t mi;
        mi.t_ns = in->t_sensor_ns;
        mi.w_meas_B_radps = w_gyro;
        mi.st.q_SN = in->st_q_SN;
        mi.st.t_meas_ns = in->st_t_meas_ns;
        mi.st.valid = 0u;
        if ((in->valid & AOCS_EXEC_VALID_ST) != 0u) {
            mi.st.valid = 1u;
        }
        st = aocs_mekf_step(s, &mi, &mo);
        if ((st == AOCS_ERR_INPUT_STALE) && (s->started != 0u) && (in->t_sensor_ns < s->t_ns)) {
            st = mekf_stage_clock_restart(s, &mi, &mo);
        }
    } else {
        /* the filter does not see this sample: its estimate as it stands, for the telemetry */
        (void)aocs_mekf_get_output(s, &mo);
        if (accept_status == AOCS_OK) {
            st = AOCS_ERR_INPUT_INVALID; /* accepted without a gyro rate (an orbit law's sample) */
        }
        mo.st_status = ((in->valid & AOCS_EXEC_VALID_ST) != 0u) ? st : AOCS_ERR_INPUT_MISSING;
    }
    if (gyro_ok != 0) {
        /* SAFE's rate damping needs only the rate: the gyro less the bias known so far */
        w_rate = aocs_vec3_sub(w_gyro, mekf_stage_bias(s));
        rate_ok = 1;
    }
    if ((st == AOCS_OK) && (gyroless != 0u) && (mekf_stage_rate_known(&mo, s->cfg.gyroless_rate_sigma_radps) == 0)) {
        /* spec 5.6.12: the dynamics' rate is not yet known well enough to point with: SAFE damps on it */
        st = AOCS_ERR_MEKF_GYROLESS_CONVERGING;
        w_rate = mo.w_BN_B_hat;
        rate_ok = 1;
    }

    out->status = st;
    if (st == AOCS_OK) {
        out->q_BN = mo.q_BN_hat;
        out->w_BN_B = mo.w_BN_B_hat;
        out->valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
    } else {
        out->q_BN = aocs_quat_identity();
        out->w_BN_B = aocs_vec3_zero();
        out->valid = 0u;
        if (rate_ok != 0) {
            out->w_BN_B = w_rate;
            out->valid = AOCS_EXEC_VALID_RATE;
        }
    }
    /* telemetry (zero bias and covariance while the filter holds no estimate) */
    out->bias_B_radps = mo.bias_B_hat;
    {
        uint32_t k = 0u;
        for (uint32_t i = 0u; i < 6u; ++i) {
            for (uint32_t j = i; j < 6u; ++j) {
                out->p_upper[k] = mo.P.m[i][j];
                ++k;
            }
        }
    }
    out->st_status = mo.st_status;
    out->n_st_used = mo.n_updates;
    out->n_st_gated = mo.n_gated;
    out->n_st_hostile = mo.n_hostile;
    out->n_restarts = mo.n_restarts;
    out->innovation_chi2 = AOCS_R(0.0);
    out->innovation_white = aocs_vec3_zero();
    if ((mo.st_status == AOCS_OK) || (mo.st_status == AOCS_ERR_MEKF_GATED) ||
        (mo.st_status == AOCS_ERR_MEKF_ST_EXCLUDED)) {
        out->innovation_chi2 = s->innovation_chi2; /* formed this step (also when the estimate is refused) */
        out->innovation_white = s->innovation_white;
    }
    return st;
}
