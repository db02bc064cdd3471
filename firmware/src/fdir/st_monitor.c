/*
 * Fault management, the star-tracker monitor (aocs/fdir/fdir.h; docs/spec.md
 * 5.15.3): the MEKF's innovation test d^2 = y^T S^-1 y (Markley & Crassidis
 * 2014, sec. 6.2 / 7.2: under the filter's model d^2 is chi-square with 3
 * degrees of freedom) against fdir.st_chi2 with persistence (exclusion) and
 * a run of consistent samples (restoration), the noise adaptation, and the
 * frozen-output test.
 *
 * The noise adaptation (5.15.3): a tracker excluded by its innovations, or one whose noise model was scaled,
 * is watched over windows of W = fdir.st_restore tested samples of its whitened innovation z = L^-1 y (N(0, I)
 * under the filter's model). With the window's mean z_m and spread m = (sum |z|^2 - W |z_m|^2) / (3 (W - 1))
 * (the mean of the per-axis sample variances), the innovation is white with zero mean when
 * W |z_m|^2 / m <= AOCS_FDIR_ST_MEAN_CHI2 (a bias step or a drift fails it: a noise increase is the one fault
 * this rescales). Excluded, white, m > 1 and the scale times m within fdir.st_noise_scale_max: the filter's
 * tracker noise variances are scaled by m and the tracker re-admitted (st_noise_rescaled, st_restored).
 * Rescaled and not excluded, white with m outside [1/4, 4] (AOCS_FDIR_ST_NOISE_BAND_LO / _HI): the scale
 * follows, times m, not below 1 (a tracker whose noise went back is trusted again).
 */
#include <stddef.h>

#include "aocs/fdir/fdir.h"

/* d^2 of this step's tracker sample when the filter tested one: 1 and *d2 */
static int st_tested(const aocs_det_output_t *est, real_t *d2)
{
    int tested = 0;
    if ((est != NULL) && ((est->st_status == AOCS_OK) || (est->st_status == AOCS_ERR_MEKF_GATED) ||
                          (est->st_status == AOCS_ERR_MEKF_ST_EXCLUDED))) {
        *d2 = est->innovation_chi2;
        tested = 1;
    }
    return tested;
}

static void st_exclude(aocs_fdir_t *f, const aocs_fdir_input_t *in, real_t value, real_t thr)
{
    if (f->st.excluded == 0) {
        (void)aocs_evlog_raise(&f->log, AOCS_EVT_ST_EXCLUDED, in->t_ns, AOCS_EVT_UNIT_NONE, value, thr);
        f->st.excluded = 1;
        f->st.good_run = 0u;
    }
}

/* the noise adaptation of the file's header, on a tested sample */
static void st_noise(aocs_fdir_t *f, const aocs_fdir_input_t *in)
{
    aocs_fdir_st_t *s = &f->st;
    const aocs_vec3_t z = in->est->innovation_white;
    int watched = 0;
    if (((s->excluded != 0) && (s->excluded_by_innovation != 0)) || (s->noise_scale > AOCS_R(1.0))) {
        watched = 1;
    }
    if ((watched == 0) || !(f->cfg.st_noise_scale_max > AOCS_R(0.0)) || (aocs_vec3_is_finite(z) == 0)) {
        s->win_n = 0u;
        s->win_sum_z = aocs_vec3_zero();
        s->win_sum_zz = AOCS_R(0.0);
    } else {
        s->win_n += 1u;
        s->win_sum_z = aocs_vec3_add(s->win_sum_z, z);
        s->win_sum_zz += aocs_vec3_norm_sq(z);
        if (s->win_n >= f->cfg.st_restore) {
            const real_t w = (real_t)s->win_n;
            const aocs_vec3_t zm = aocs_vec3_scale(s->win_sum_z, AOCS_R(1.0) / w);
            const real_t mean2 = aocs_vec3_norm_sq(zm);
            const real_t m = (w > AOCS_R(1.0)) ? ((s->win_sum_zz - (w * mean2)) / (AOCS_R(3.0) * (w - AOCS_R(1.0))))
                                               : AOCS_R(0.0);
            const real_t scale = s->noise_scale * m;
            int white = 0;
            if ((m > AOCS_R(0.0)) && ((w * mean2) <= (AOCS_FDIR_ST_MEAN_CHI2 * m))) {
                white = 1;
            }
            if ((white != 0) && (s->excluded != 0) && (m > AOCS_R(1.0)) && (scale <= f->cfg.st_noise_scale_max)) {
                s->noise_scale = scale;
                f->st_rescaled = 1;
                (void)aocs_evlog_raise(&f->log, AOCS_EVT_ST_NOISE_RESCALED, in->t_ns, AOCS_EVT_UNIT_NONE,
                                       AOCS_SQRT(scale), AOCS_SQRT(f->cfg.st_noise_scale_max));
                (void)aocs_evlog_raise(&f->log, AOCS_EVT_ST_RESTORED, in->t_ns, AOCS_EVT_UNIT_NONE, m,
                                       AOCS_R(1.0));
                s->excluded = 0;
                s->excluded_by_innovation = 0;
                s->good_run = 0u;
                s->high_run = 0u;
            } else if ((white != 0) && (s->excluded == 0) && ((m < AOCS_FDIR_ST_NOISE_BAND_LO) ||
                                                              (m > AOCS_FDIR_ST_NOISE_BAND_HI))) {
                real_t k = (scale > f->cfg.st_noise_scale_max) ? f->cfg.st_noise_scale_max : scale;
                if (k < AOCS_R(1.0)) {
                    k = AOCS_R(1.0);
                }
                s->noise_scale = k;
                f->st_rescaled = 1;
                (void)aocs_evlog_raise(&f->log, AOCS_EVT_ST_NOISE_RESCALED, in->t_ns, AOCS_EVT_UNIT_NONE,
                                       AOCS_SQRT(k), AOCS_SQRT(f->cfg.st_noise_scale_max));
            } else {
                /* not white, or within its model: nothing to change */
            }
            s->win_n = 0u;
            s->win_sum_z = aocs_vec3_zero();
            s->win_sum_zz = AOCS_R(0.0);
        }
    }
}

/* tested: the filter tested this step's sample, with innovation d2 */
static void st_innovation(aocs_fdir_t *f, const aocs_fdir_input_t *in, int tested, real_t d2)
{
    const real_t thr = f->cfg.st_chi2;
    if (tested != 0) {
        if (!(d2 <= thr)) {
            f->st.high_run = aocs_fdir_count_up(f->st.high_run);
            f->st.good_run = 0u;
        } else {
            f->st.high_run = 0u;
            if ((f->st.excluded != 0) && (f->st.frozen_run == 0u)) {
                f->st.good_run = aocs_fdir_count_up(f->st.good_run);
            }
        }
        if ((f->st.high_run == f->cfg.st_persist) && (f->st.excluded == 0)) {
            (void)aocs_evlog_raise(&f->log, AOCS_EVT_ST_INNOVATION_HIGH, in->t_ns, AOCS_EVT_UNIT_NONE, d2, thr);
            st_exclude(f, in, d2, thr);
            f->st.excluded_by_innovation = 1;
            f->st.win_n = 0u; /* the window starts with the exclusion */
            f->st.win_sum_z = aocs_vec3_zero();
            f->st.win_sum_zz = AOCS_R(0.0);
        }
        if ((f->st.excluded != 0) && (f->st.good_run >= f->cfg.st_restore)) {
            (void)aocs_evlog_raise(&f->log, AOCS_EVT_ST_RESTORED, in->t_ns, AOCS_EVT_UNIT_NONE, d2, thr);
            f->st.excluded = 0;
            f->st.excluded_by_innovation = 0;
            f->st.good_run = 0u;
        } else {
            st_noise(f, in);
        }
    }
}

static int st_same(aocs_quat_t a, aocs_quat_t b)
{
    int same = 1;
    for (int i = 0; i < 4; ++i) {
        if (aocs_fdir_same(a.q[i], b.q[i]) == 0) {
            same = 0;
        }
    }
    return same;
}

/* K identical quaternions in a row while the gyro says the body turns faster than st_frozen_rate_radps (a
 * noise-free tracker repeats itself on a body at rest), or at any rate when the MEKF tested the sample: it
 * models the tracker with a noise sigma > 0 (its configuration check refuses less), and a tracker with noise
 * never repeats its quaternion to the last bit, so K repeats are a frozen output in a hold too (5.15.3) */
static void st_frozen(aocs_fdir_t *f, const aocs_fdir_input_t *in, int noisy)
{
    if (in->st_valid != 0) {
        const real_t rate = (in->gyro_valid != 0) ? aocs_vec3_norm(in->gyro_w_B) : AOCS_R(0.0);
        if ((f->st.have_prev != 0) && (st_same(in->st_q_SN, f->st.q_prev_SN) != 0) &&
            ((noisy != 0) || (rate > f->cfg.st_frozen_rate_radps))) {
            f->st.frozen_run = aocs_fdir_count_up(f->st.frozen_run);
        } else {
            f->st.frozen_run = 0u;
        }
        /* K identical samples = K - 1 repeats */
        if (f->st.frozen_run == (f->cfg.st_frozen_samples - 1u)) {
            (void)aocs_evlog_raise(&f->log, AOCS_EVT_ST_FROZEN, in->t_ns, AOCS_EVT_UNIT_NONE, rate,
                                   f->cfg.st_frozen_rate_radps);
            st_exclude(f, in, rate, f->cfg.st_frozen_rate_radps);
            f->st.excluded_by_innovation = 0; /* frozen: no noise to adapt to */
        }
        f->st.q_prev_SN = in->st_q_SN;
        f->st.have_prev = 1;
    }
}

void aocs_fdir_st_step(aocs_fdir_t *f, const aocs_fdir_input_t *in)
{
    real_t d2 = AOCS_R(0.0);
    const int tested = st_tested(in->est, &d2); /* once: both tests read it */
    st_frozen(f, in, tested);
    st_innovation(f, in, tested, d2);
}
