/*
 * Fault management, the gyro monitor (aocs/fdir/fdir.h; docs/spec.md
 * 5.15.4): saturation (a component at or beyond fdir.gyro_sat_radps on
 * fdir.gyro_stuck_samples samples) and a stuck axis (one component
 * bit-identical on fdir.gyro_stuck_samples samples while another component
 * changed: a live gyro's noise never repeats a value, a noise-free one repeats
 * on every axis at once). Either excludes the gyro: the one rate sensor, so
 * nothing is left to propagate on and SAFE is latched (gyro_excluded).
 */
#include <stddef.h>

#include "aocs/fdir/fdir.h"

static void gyro_exclude(aocs_fdir_t *f, const aocs_fdir_input_t *in, uint32_t axis, real_t value, real_t thr)
{
    if (f->gyro.excluded == 0) {
        (void)aocs_evlog_raise(&f->log, AOCS_EVT_GYRO_EXCLUDED, in->t_ns, (int32_t)axis, value, thr);
        f->gyro.excluded = 1;
        f->safe_latched = 1;
    }
}

void aocs_fdir_gyro_step(aocs_fdir_t *f, const aocs_fdir_input_t *in)
{
    aocs_fdir_gyro_t *g = &f->gyro;
    if ((in->gyro_valid != 0) && (aocs_vec3_is_finite(in->gyro_w_B) != 0)) {
        const uint32_t k = f->cfg.gyro_stuck_samples;
        int other_changed[3] = {0, 0, 0};
        if (g->have_prev != 0) {
            for (uint32_t i = 0u; i < 3u; ++i) {
                for (uint32_t j = 0u; j < 3u; ++j) {
                    if ((j != i) && (aocs_fdir_same(in->gyro_w_B.v[j], g->w_prev_B.v[j]) == 0)) {
                        other_changed[i] = 1;
                    }
                }
            }
        }
        for (uint32_t i = 0u; i < 3u; ++i) {
            const real_t w = in->gyro_w_B.v[i];
            if ((g->have_prev != 0) && (aocs_fdir_same(w, g->w_prev_B.v[i]) != 0) && (other_changed[i] != 0)) {
                g->stuck_run[i] = aocs_fdir_count_up(g->stuck_run[i]);
            } else {
                g->stuck_run[i] = 0u;
            }
            if ((f->cfg.gyro_sat_radps > AOCS_R(0.0)) && (AOCS_FABS(w) >= f->cfg.gyro_sat_radps)) {
                g->sat_run[i] = aocs_fdir_count_up(g->sat_run[i]);
            } else {
                g->sat_run[i] = 0u;
            }
            /* k identical samples = k - 1 repeats */
            if (g->stuck_run[i] == (k - 1u)) {
                (void)aocs_evlog_raise(&f->log, AOCS_EVT_GYRO_STUCK, in->t_ns, (int32_t)i, w, AOCS_R(0.0));
                gyro_exclude(f, in, i, w, AOCS_R(0.0));
            }
            if (g->sat_run[i] == k) {
                (void)aocs_evlog_raise(&f->log, AOCS_EVT_GYRO_SATURATED, in->t_ns, (int32_t)i, AOCS_FABS(w),
                                       f->cfg.gyro_sat_radps);
                gyro_exclude(f, in, i, AOCS_FABS(w), f->cfg.gyro_sat_radps);
            }
        }
        g->w_prev_B = in->gyro_w_B;
        g->have_prev = 1;
    } else {
        g->have_prev = 0;
    }
}
