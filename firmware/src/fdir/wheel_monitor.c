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
 *
 * Friction (spec 5.15.2): a friction f = s f^ leaves r = (s - 1) f^, far below the isolation threshold for a
 * wheel whose friction grew a few times; over fdir.wheel_friction_window steps of one sign of f^, sum r / sum f^
 * = s - 1 (the tachometers' noise telescopes in sum r: only the window's two ends count; a window holding a
 * residual above the isolation threshold, a dead motor or a tachometer jump, is not judged). Above
 * fdir.wheel_friction_excess the wheel's friction is high (wheel_friction_high, value s) and its friction model,
 * viscous and Coulomb, is scaled by s (aocs_wheels_set_friction): the feedforward compensates the friction the
 * wheel has. From then on the model follows the wheel: a later window off by more than a tenth of the threshold
 * scales it again (no new event), so a window that held the change only in part does not leave it short.
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

/* Scales wheel i's friction model by s (its viscous and Coulomb terms), or leaves it when the array refuses
 * it (the friction then beyond the motor's limit). */
static void wheels_refit_friction(aocs_wheels_t *wa, uint32_t i, real_t s)
{
    (void)aocs_wheels_set_friction(wa, i, wa->cfg.viscous_nms[i] * s, wa->cfg.coulomb_nm[i] * s);
}

/* The friction test at the end of a window: each healthy wheel whose friction model kept one sign and at
 * least half its Coulomb level on average (a wheel spinning one way: the ratio is then well defined). */
static void wheels_friction_window_end(aocs_fdir_t *f, const aocs_fdir_input_t *in, aocs_wheels_t *wa)
{
    aocs_fdir_wheels_t *w = &f->wheels;
    for (uint32_t i = 0u; (i < wa->cfg.n) && (i < AOCS_WHEELS_MAX); ++i) {
        const real_t level = AOCS_R(0.5) * (real_t)w->friction_steps * wa->cfg.coulomb_nm[i];
        const uint32_t skip = wa->cfg.failed_mask | w->friction_tainted_mask;
        if (((skip & fdir_wheel_bit(i)) == 0u) && (level > AOCS_R(0.0)) &&
            (AOCS_FABS(w->sum_f_nm[i]) >= level) && (AOCS_FABS(w->sum_f_nm[i]) >= (AOCS_R(0.5) * w->sum_abs_f_nm[i]))) {
            const real_t excess = w->sum_r_nm[i] / w->sum_f_nm[i];
            const uint32_t known = w->friction_high_mask & fdir_wheel_bit(i);
            if ((known == 0u) && (excess > f->cfg.wheel_friction_excess)) {
                (void)aocs_evlog_raise(&f->log, AOCS_EVT_WHEEL_FRICTION_HIGH, in->t_ns, (int32_t)i,
                                       AOCS_R(1.0) + excess, AOCS_R(1.0) + f->cfg.wheel_friction_excess);
                w->friction_high_mask |= fdir_wheel_bit(i);
                wheels_refit_friction(wa, i, AOCS_R(1.0) + excess);
            } else if ((known != 0u) && (AOCS_FABS(excess) > (AOCS_R(0.1) * f->cfg.wheel_friction_excess)) &&
                       (excess > AOCS_R(-1.0))) {
                wheels_refit_friction(wa, i, AOCS_R(1.0) + excess);
            } else {
                /* within the model */
            }
        }
        w->sum_r_nm[i] = AOCS_R(0.0);
        w->sum_f_nm[i] = AOCS_R(0.0);
        w->sum_abs_f_nm[i] = AOCS_R(0.0);
    }
    w->friction_steps = 0u;
    w->friction_tainted_mask = 0u;
}

static void wheels_detect(aocs_fdir_t *f, const aocs_fdir_input_t *in, aocs_wheels_t *wa, uint32_t i, real_t thr)
{
    aocs_fdir_wheels_t *w = &f->wheels;
    const real_t r = aocs_fdir_wheel_residual(w->u_net_prev_nm[i], wa->cfg.js_kgm2[i], w->omega_prev_radps[i],
                                              in->wheel_speed_radps[i], in->period_s);
    if (AOCS_IS_FINITE(r) && AOCS_IS_FINITE(w->f_prev_nm[i]) && (AOCS_FABS(r) <= thr)) {
        w->sum_r_nm[i] += r;
        w->sum_f_nm[i] += w->f_prev_nm[i];
        w->sum_abs_f_nm[i] += AOCS_FABS(w->f_prev_nm[i]);
    } else {
        /* a residual the isolation test owns (a dead motor, a tachometer jump): not friction, and the window
         * that holds it is not judged */
        w->friction_tainted_mask |= fdir_wheel_bit(i);
    }
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
            w->friction_steps = aocs_fdir_count_up(w->friction_steps);
            if ((f->cfg.wheel_friction_excess > AOCS_R(0.0)) && (w->friction_steps >= f->cfg.wheel_friction_window)) {
                wheels_friction_window_end(f, in, wheels);
            }
        }
        /* this step's command for the next step's test: held over the period that starts now */
        for (uint32_t i = 0u; (i < wheels->cfg.n) && (i < AOCS_WHEELS_MAX); ++i) {
            const real_t om = in->wheel_speed_radps[i];
            w->omega_prev_radps[i] = om;
            w->f_prev_nm[i] = aocs_wheels_friction(wheels, i, om);
            w->u_net_prev_nm[i] = in->alloc->u_s_nm[i] - w->f_prev_nm[i];
        }
        /* the allocation replaced by zero (its guard) commands nothing: the wheels still coast, the test holds */
        w->have_prev = 1;
    } else {
        w->have_prev = 0;
    }
}
