/*
 * Fault management, the gyro monitor (aocs/fdir/fdir.h; docs/spec.md
 * 5.15.4): saturation (a component at or beyond fdir.gyro_sat_radps on
 * fdir.gyro_stuck_samples samples) and a stuck axis (one component
 * bit-identical on fdir.gyro_stuck_samples samples while another component
 * changed: a live gyro's noise never repeats a value, a noise-free one repeats
 * on every axis at once). Either excludes the gyro (gyro_excluded): the one
 * rate sensor, so the estimator goes on without it when it can (the MEKF's
 * gyroless model, spec 5.6.12: estimator_gyroless), else nothing is left to
 * propagate on and SAFE is latched. The executive no longer shows an excluded
 * gyro to the monitors.
 *
 * A gyro whose every axis repeats is either noise-free at a constant rate or pinned (saturated on every
 * axis, or stuck): the tracker tells them apart. Over such a run the tracker's rotation, the angle of
 * q_SN(t) (x) q_SN(t_0)^-1 (frame-free), is the gyro's sum |w| T for a constant rate; a tracker turning
 * faster than that by AOCS_FDIR_GYRO_PINNED_RATE_FACTOR fdir.st_frozen_rate_radps over
 * fdir.gyro_stuck_samples samples makes the gyro stuck (gyro_stuck, the axis of the largest reading), and
 * the tracker, if its innovations (which the pinned gyro spoiled) had excluded it, is restored.
 */
#include <stddef.h>

#include "aocs/fdir/fdir.h"

static void gyro_exclude(aocs_fdir_t *f, const aocs_fdir_input_t *in, uint32_t axis, real_t value, real_t thr)
{
    if (f->gyro.excluded == 0) {
        (void)aocs_evlog_raise(&f->log, AOCS_EVT_GYRO_EXCLUDED, in->t_ns, (int32_t)axis, value, thr);
        f->gyro.excluded = 1;
        if (in->gyroless_capable != 0) {
            /* spec 5.6.12: the estimator goes on without it (applied by the executive) */
            (void)aocs_evlog_raise(&f->log, AOCS_EVT_ESTIMATOR_GYROLESS, in->t_ns, AOCS_EVT_UNIT_NONE, value, thr);
            f->go_gyroless = 1;
        } else {
            f->safe_latched = 1;
        }
    }
}

/* The pinned test (see the file's header) for a sample with every axis identical to the last (same) or not. */
static void gyro_pinned(aocs_fdir_t *f, const aocs_fdir_input_t *in, int same)
{
    aocs_fdir_gyro_t *g = &f->gyro;
    if (same != 0) {
        g->pinned_run = aocs_fdir_count_up(g->pinned_run);
        if (g->pinned_run == 1u) {
            g->st_ref_SN = g->st_last_SN;
            g->have_st_ref = g->have_st_last;
            g->pinned_angle_rad = AOCS_R(0.0);
            g->pinned_span_s = AOCS_R(0.0);
        }
        g->pinned_angle_rad += aocs_vec3_norm(in->gyro_w_B) * in->period_s;
        g->pinned_span_s += in->period_s;
        if ((g->pinned_run == (f->cfg.gyro_stuck_samples - 1u)) && (g->have_st_ref != 0) && (in->st_valid != 0) &&
            (aocs_quat_is_finite(in->st_q_SN) != 0)) {
            const real_t turned = aocs_quat_angle(aocs_quat_error(in->st_q_SN, g->st_ref_SN));
            const real_t bound = g->pinned_angle_rad +
                                 (AOCS_FDIR_GYRO_PINNED_RATE_FACTOR * f->cfg.st_frozen_rate_radps * g->pinned_span_s);
            if (turned > bound) {
                uint32_t axis = 0u;
                for (uint32_t i = 1u; i < 3u; ++i) {
                    if (AOCS_FABS(in->gyro_w_B.v[i]) > AOCS_FABS(in->gyro_w_B.v[axis])) {
                        axis = i;
                    }
                }
                (void)aocs_evlog_raise(&f->log, AOCS_EVT_GYRO_STUCK, in->t_ns, (int32_t)axis,
                                       turned / g->pinned_span_s, bound / g->pinned_span_s);
                gyro_exclude(f, in, axis, turned / g->pinned_span_s, bound / g->pinned_span_s);
                if ((f->st.excluded != 0) && (f->st.frozen_run == 0u)) {
                    /* its innovations were the gyro's doing: the tracker is used again */
                    f->st.excluded = 0;
                    f->st.excluded_by_innovation = 0;
                    f->st.good_run = 0u;
                    (void)aocs_evlog_raise(&f->log, AOCS_EVT_ST_RESTORED, in->t_ns, AOCS_EVT_UNIT_NONE, turned,
                                           bound);
                }
            }
        }
    } else {
        g->pinned_run = 0u;
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
        gyro_pinned(f, in, ((g->have_prev != 0) && (aocs_fdir_same(in->gyro_w_B.v[0], g->w_prev_B.v[0]) != 0) &&
                            (aocs_fdir_same(in->gyro_w_B.v[1], g->w_prev_B.v[1]) != 0) &&
                            (aocs_fdir_same(in->gyro_w_B.v[2], g->w_prev_B.v[2]) != 0)) ? 1 : 0);
        g->w_prev_B = in->gyro_w_B;
        g->have_prev = 1;
    } else {
        g->have_prev = 0;
        g->pinned_run = 0u;
    }
    if ((in->st_valid != 0) && (aocs_quat_is_finite(in->st_q_SN) != 0)) {
        g->st_last_SN = in->st_q_SN;
        g->have_st_last = 1;
    }
}
