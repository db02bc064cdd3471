/*
 * The fault-management stage (aocs/fdir/fdir.h; docs/spec.md 5.15): its
 * configuration, and the step that runs the monitors and the mode and link
 * supervision (safe_entered / safe_left, link_lost / link_restored).
 */
#include <stddef.h>
#include <string.h>

#include "aocs/fdir/fdir.h"

int aocs_fdir_same(real_t a, real_t b)
{
    return ((a <= b) && (a >= b)) ? 1 : 0;
}

uint32_t aocs_fdir_count_up(uint32_t n)
{
    uint32_t m = n;
    if (m < UINT32_MAX) {
        m += 1u;
    }
    return m;
}

void aocs_fdir_config_default(aocs_fdir_config_t *cfg)
{
    if (cfg != NULL) {
        cfg->enabled = 1u;
        cfg->wheel_residual_frac = AOCS_FDIR_WHEEL_RESIDUAL_FRAC_DEFAULT;
        cfg->wheel_persist = AOCS_FDIR_WHEEL_PERSIST_DEFAULT;
        cfg->st_chi2 = AOCS_FDIR_ST_CHI2_DEFAULT;
        cfg->st_persist = AOCS_FDIR_ST_PERSIST_DEFAULT;
        cfg->st_restore = AOCS_FDIR_ST_RESTORE_DEFAULT;
        cfg->st_frozen_samples = AOCS_FDIR_ST_FROZEN_SAMPLES_DEFAULT;
        cfg->st_frozen_rate_radps = AOCS_FDIR_ST_FROZEN_RATE_DEFAULT;
        cfg->gyro_stuck_samples = AOCS_FDIR_GYRO_STUCK_SAMPLES_DEFAULT;
        cfg->gyro_sat_radps = AOCS_FDIR_GYRO_SAT_DEFAULT;
        cfg->gyro_bias_chi2 = AOCS_FDIR_GYRO_BIAS_CHI2_DEFAULT;
        cfg->gyro_bias_persist = AOCS_FDIR_GYRO_BIAS_PERSIST_DEFAULT;
        cfg->link_lost_periods = AOCS_FDIR_LINK_LOST_PERIODS_DEFAULT;
        cfg->mom_residual_nm = AOCS_FDIR_MOM_RESIDUAL_DEFAULT;
        cfg->mom_window = AOCS_FDIR_MOM_WINDOW_DEFAULT;
        cfg->mom_persist = AOCS_FDIR_MOM_PERSIST_DEFAULT;
        cfg->thr_open_persist = AOCS_FDIR_THR_OPEN_PERSIST_DEFAULT;
        cfg->wheel_friction_window = AOCS_FDIR_WHEEL_FRICTION_WINDOW_DEFAULT;
        cfg->wheel_friction_excess = AOCS_FDIR_WHEEL_FRICTION_EXCESS_DEFAULT;
        cfg->st_noise_scale_max = AOCS_FDIR_ST_NOISE_SCALE_MAX_DEFAULT;
    }
}

aocs_status_t aocs_fdir_config_check(const aocs_fdir_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (cfg == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (cfg->enabled == 0u) {
        st = AOCS_OK; /* off: the other values are not used (a zeroed configuration is a disabled stage) */
    } else if ((cfg->enabled > 1u) || !(cfg->wheel_residual_frac > AOCS_R(0.0)) ||
               !(cfg->wheel_residual_frac <= AOCS_R(1.0)) || (cfg->wheel_persist == 0u) ||
               !(cfg->st_chi2 > AOCS_R(0.0)) || !AOCS_IS_FINITE(cfg->st_chi2) || (cfg->st_persist == 0u) ||
               (cfg->st_restore == 0u) || (cfg->st_frozen_samples < 2u) || !(cfg->st_frozen_rate_radps > AOCS_R(0.0)) ||
               !AOCS_IS_FINITE(cfg->st_frozen_rate_radps) || (cfg->gyro_stuck_samples < 2u) ||
               !(cfg->gyro_sat_radps >= AOCS_R(0.0)) || !AOCS_IS_FINITE(cfg->gyro_sat_radps) ||
               !(cfg->gyro_bias_chi2 >= AOCS_R(0.0)) || !AOCS_IS_FINITE(cfg->gyro_bias_chi2) ||
               (cfg->gyro_bias_persist == 0u) || (cfg->link_lost_periods == 0u) ||
               !(cfg->mom_residual_nm >= AOCS_R(0.0)) || !AOCS_IS_FINITE(cfg->mom_residual_nm) ||
               (cfg->mom_window == 0u) || (cfg->mom_persist == 0u) || (cfg->thr_open_persist == 0u) ||
               (cfg->wheel_friction_window == 0u) ||
               !(cfg->wheel_friction_excess >= AOCS_R(0.0)) || !AOCS_IS_FINITE(cfg->wheel_friction_excess) ||
               !(cfg->st_noise_scale_max >= AOCS_R(0.0)) || !AOCS_IS_FINITE(cfg->st_noise_scale_max)) {
        st = AOCS_ERR_FDIR_CONFIG_INVALID;
    } else {
        st = AOCS_OK;
    }
    return st;
}

aocs_status_t aocs_fdir_init(aocs_fdir_t *f, const aocs_fdir_config_t *cfg)
{
    aocs_status_t st = AOCS_ERR_NULL_ARG;
    if (f != NULL) {
        (void)memset(f, 0, sizeof(*f));
        st = aocs_fdir_config_check(cfg);
        if (st == AOCS_OK) {
            f->cfg = *cfg;
            aocs_evlog_init(&f->log);
            f->mode_prev = AOCS_EXEC_MODE_STANDBY;
            f->st.noise_scale = AOCS_R(1.0);
            f->initialised = 1;
        }
    }
    return st;
}

/* link_lost at the link_lost_periods-th consecutive period without a sample (a tick gap counts its missed
 * samples at once), link_restored at the next sample (value: the periods missed). */
static void fdir_link(aocs_fdir_t *f, const aocs_fdir_input_t *in)
{
    const real_t thr = (real_t)f->cfg.link_lost_periods;
    if (in->have_sample == 0) {
        if (f->missing_run < UINT32_MAX) {
            f->missing_run += 1u;
        }
    } else {
        f->missing_run = ((UINT32_MAX - f->missing_run) < in->missing) ? UINT32_MAX : (f->missing_run + in->missing);
    }
    if ((f->link_down == 0u) && (f->missing_run >= f->cfg.link_lost_periods)) {
        (void)aocs_evlog_raise(&f->log, AOCS_EVT_LINK_LOST, in->t_ns, AOCS_EVT_UNIT_NONE, (real_t)f->missing_run, thr);
        f->link_down = 1u;
    }
    if (in->have_sample != 0) {
        if (f->link_down != 0u) {
            (void)aocs_evlog_raise(&f->log, AOCS_EVT_LINK_RESTORED, in->t_ns, AOCS_EVT_UNIT_NONE,
                                   (real_t)f->missing_run, thr);
            f->link_down = 0u;
        }
        f->missing_run = 0u;
    }
}

/* safe_entered / safe_left: the mode changes after the first NOMINAL step (the start-up SAFE of an
 * estimator still waiting for its first attitude is acquisition, not a fault) */
static void fdir_modes(aocs_fdir_t *f, const aocs_fdir_input_t *in)
{
    if (f->flown_nominal != 0) {
        if ((in->mode == AOCS_EXEC_MODE_SAFE) && (f->mode_prev != AOCS_EXEC_MODE_SAFE)) {
            aocs_status_t why = in->input_status;
            if ((why == AOCS_OK) && (in->est != NULL)) {
                why = in->est->status;
            }
            (void)aocs_evlog_raise(&f->log, AOCS_EVT_SAFE_ENTERED, in->t_ns, AOCS_EVT_UNIT_NONE, (real_t)why,
                                   AOCS_R(0.0));
        } else if ((in->mode == AOCS_EXEC_MODE_NOMINAL) && (f->mode_prev == AOCS_EXEC_MODE_SAFE)) {
            (void)aocs_evlog_raise(&f->log, AOCS_EVT_SAFE_LEFT, in->t_ns, AOCS_EVT_UNIT_NONE, AOCS_R(0.0),
                                   AOCS_R(0.0));
        } else {
            /* no change */
        }
    }
    if (in->mode == AOCS_EXEC_MODE_NOMINAL) {
        f->flown_nominal = 1;
    }
    f->mode_prev = in->mode;
}

void aocs_fdir_step(aocs_fdir_t *f, const aocs_fdir_input_t *in, aocs_wheels_t *wheels)
{
    if ((f != NULL) && (in != NULL) && (f->initialised != 0)) {
        f->replan = 0;
        f->reinflate_bias = 0;
        f->go_gyroless = 0;
        f->st_rescaled = 0;
        if (f->cfg.enabled != 0u) {
            fdir_link(f, in);
            if ((in->have_sample != 0) && (in->input_status == AOCS_OK)) {
                aocs_fdir_wheels_step(f, in, wheels);
                aocs_fdir_st_step(f, in);
                aocs_fdir_gyro_step(f, in);
                aocs_fdir_gyro_bias_step(f, in);
                aocs_fdir_mom_step(f, in, wheels);
            } else {
                /* no usable sample: the differences restart from the next one */
                f->wheels.have_prev = 0;
                f->st.have_prev = 0;
                f->gyro.have_prev = 0;
                f->gyro.pinned_run = 0u;
                f->mom.open = 0;
                f->mom.have_hw_prev = 0;
            }
            fdir_modes(f, in);
        }
    }
}
