/*
 * Fault management, the wheel monitor (aocs/fdir/fdir.h; docs/spec.md
 * 5.15.2): the residual between the net axial torque commanded over the last
 * period and the one the tachometers measured, with a persistence counter per
 * wheel; isolation of a wheel by re-initialising the array without it.
 *
 *   r_i(k) = [u_s,i - f^_i(Omega_i)](k-1) - Js_i (Omega_i(k) - Omega_i(k-1)) / T
 *
 * u_s is the motor command held over the period, f^ the friction model of the
 * allocation (wheel_array.h) at the speed the period started from; the wheel's
 * own equation is Js dOmega/dt = u_s - f(Omega) - Js g_i . dw/dt (spec 5.3), so
 * r_i is the motor torque the wheel did not deliver, up to the friction
 * model's error over the period and Js g . dw/dt (both bounded in spec 5.15.2).
 */
#include <stddef.h>

#include "aocs/fdir/fdir.h"

real_t aocs_fdir_wheel_residual(real_t u_net_prev_nm, real_t js_kgm2, real_t omega_prev_radps, real_t omega_radps,
                                real_t period_s)
{
    return u_net_prev_nm - ((js_kgm2 * (omega_radps - omega_prev_radps)) / period_s);
}

static uint32_t fdir_wheel_bit(uint32_t i)
{
    return (uint32_t)1u << i;
}

/* Removes wheel i from the array: AOCS_OK and *wa re-initialised (Gs^+ over the wheels left; the array as it
 * was kept in *before), or the array's refusal (AOCS_ERR_WHEELS_NOT_SPANNING: fewer than 3 wheels left, or
 * they do not span) with *wa untouched. */
static aocs_status_t wheels_isolate(aocs_wheels_t *wa, uint32_t i, aocs_wheels_t *before)
{
    aocs_wheels_t trial;
    aocs_wheels_config_t cfg = wa->cfg;
    aocs_status_t st;
    cfg.failed_mask |= fdir_wheel_bit(i);
    st = aocs_wheels_init(&trial, &cfg);
    if (st == AOCS_OK) {
        *before = *wa;
        *wa = trial;
    }
    return st;
}

static void wheels_detect(aocs_fdir_t *f, const aocs_fdir_input_t *in, aocs_wheels_t *wa, uint32_t i, real_t thr)
{
    aocs_fdir_wheels_t *w = &f->wheels;
    const real_t r = aocs_fdir_wheel_residual(w->u_net_prev_nm[i], wa->cfg.js_kgm2[i], w->omega_prev_radps[i],
                                              in->wheel_speed_radps[i], in->period_s);
    if (!(AOCS_FABS(r) <= thr)) {
        w->over[i] = aocs_fdir_count_up(w->over[i]);
    } else {
        w->over[i] = 0u;
    }
    if (w->over[i] == f->cfg.wheel_persist) {
        (void)aocs_evlog_raise(&f->log, AOCS_EVT_WHEEL_RESIDUAL_HIGH, in->t_ns, (int32_t)i, AOCS_FABS(r), thr);
        if (wheels_isolate(wa, i, &f->wheels_before) == AOCS_OK) {
            (void)aocs_evlog_raise(&f->log, AOCS_EVT_WHEEL_ISOLATED, in->t_ns, (int32_t)i, AOCS_FABS(r), thr);
            f->replan = 1;
        } else {
            (void)aocs_evlog_raise(&f->log, AOCS_EVT_WHEEL_ISOLATION_REFUSED, in->t_ns, (int32_t)i, AOCS_FABS(r),
                                   thr);
            f->safe_latched = 1;
        }
    }
}

void aocs_fdir_wheels_step(aocs_fdir_t *f, const aocs_fdir_input_t *in, aocs_wheels_t *wheels)
{
    aocs_fdir_wheels_t *w = &f->wheels;
    if ((wheels != NULL) && (wheels->initialised != 0) && (in->wheel_speed_radps != NULL) && (in->alloc != NULL) &&
        (in->period_s > AOCS_R(0.0))) {
        if (w->have_prev != 0) {
            for (uint32_t i = 0u; (i < wheels->cfg.n) && (i < AOCS_WHEELS_MAX); ++i) {
                if ((wheels->cfg.failed_mask & fdir_wheel_bit(i)) == 0u) {
                    wheels_detect(f, in, wheels, i, f->cfg.wheel_residual_frac * wheels->cfg.u_max_nm[i]);
                } else {
                    w->over[i] = 0u;
                }
            }
        }
        /* this step's command for the next step's test: held over the period that starts now */
        for (uint32_t i = 0u; (i < wheels->cfg.n) && (i < AOCS_WHEELS_MAX); ++i) {
            const real_t om = in->wheel_speed_radps[i];
            w->omega_prev_radps[i] = om;
            w->u_net_prev_nm[i] = in->alloc->u_s_nm[i] - aocs_wheels_friction(wheels, i, om);
        }
        /* the allocation replaced by zero (its guard) commands nothing: the wheels still coast, the test holds */
        w->have_prev = 1;
    } else {
        w->have_prev = 0;
    }
}
