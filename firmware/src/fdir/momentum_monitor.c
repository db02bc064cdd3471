/*
 * Fault management, the momentum monitor (aocs/fdir/fdir.h; docs/spec.md 5.15.8): the total angular momentum of
 * the spacecraft and its wheels, in the inertial frame, against the impulse the thrusters were commanded to
 * give. Euler's law for the whole system, dH_N/dt = tau_ext,N, over a window of M control periods from t_0:
 *
 *   r = H_N(t_M) - H_N(t_0) - sum_k sum_i A(q_k)^T tau_i t_on,i(k),     H_N = A(q)^T (J w + sum_i Js_i g_i Omega_i)
 *
 * (A(q) the attitude matrix B <- N of the estimate, tau_i the torque of thruster i at full thrust, t_on,i(k) its
 * on-time over period k). The rate estimate may be the gyro's mean over the period before the sample (a rate-
 * integrating gyro through the MEKF) or the rate at the sample (the ideal rate sensor): the two differ by J
 * alpha T / 2, and J alpha is, but for the external torque, the wheels' -dh_w/dt, so each end of a window
 * carries an epoch uncertainty of e = |h_w(k) - h_w(k-1)| / 2, added to the window's bound. Internal torques
 * (wheels, their friction, a wheel that fails) leave H unchanged; what is left in r is the external torque the
 * flight software does not command (the environment's, bounded by the mission: fdir.mom_residual_nm is that
 * bound's mean over a window) and what a thruster did not do. A window with |r| > mom_residual_nm M T + e_0 +
 * e_M is inconsistent (a slew's acceleration widens it by up to the wheels' torque times T, a hold's by the
 * dump's); it is explained by thruster i when adding back its commanded impulse c_i brings it inside (|r + c_i|
 * <= the same bound): the thruster was commanded and did not fire. fdir.mom_persist such windows in a row naming
 * the same thruster raise thruster_ineffective, and the thruster is taken out of the allocation
 * (aocs_mom_thr_exclude; unload_actuator_switched: the dump goes on with the rest of the set); as many not explained raise
 * momentum_inconsistent (a thruster stuck open, an unmodelled torque: nothing to isolate it with). The test is
 * off with mom_residual_nm = 0, without a wheel array or an estimate, and after a wheel isolation (the isolated
 * wheel's tachometer may be the fault, and its momentum is then unknown).
 */
#include <stddef.h>

#include "aocs/fdir/fdir.h"

static void mom_open(aocs_fdir_mom_t *m, aocs_vec3_t h_N, real_t epoch_Nms)
{
    m->h_ref_N = h_N;
    m->epoch_ref_Nms = epoch_Nms;
    m->expected_N = aocs_vec3_zero();
    for (uint32_t i = 0u; i < AOCS_MOM_THRUSTERS_MAX; ++i) {
        m->thr_impulse_N[i] = aocs_vec3_zero();
    }
    m->periods = 0u;
    m->open = 1;
}

/* The commanded thruster whose impulse, added back, brings r inside bound (the one leaving the smallest
 * residual); AOCS_MOM_THRUSTERS_MAX when none. */
static uint32_t mom_explaining_thruster(const aocs_fdir_mom_t *m, aocs_vec3_t r, real_t bound)
{
    uint32_t best = AOCS_MOM_THRUSTERS_MAX;
    real_t best_norm = bound;
    for (uint32_t i = 0u; i < AOCS_MOM_THRUSTERS_MAX; ++i) {
        if (aocs_vec3_norm(m->thr_impulse_N[i]) > AOCS_R(0.0)) {
            const real_t n = aocs_vec3_norm(aocs_vec3_add(r, m->thr_impulse_N[i]));
            if (n <= best_norm) {
                best_norm = n;
                best = i;
            }
        }
    }
    return best;
}

/* A window has closed: judge r, count, raise, isolate. */
static void mom_judge(aocs_fdir_t *f, const aocs_fdir_input_t *in, aocs_vec3_t h_N, real_t epoch_Nms)
{
    aocs_fdir_mom_t *m = &f->mom;
    const real_t span_s = (real_t)m->periods * in->period_s;
    const real_t bound = (f->cfg.mom_residual_nm * span_s) + m->epoch_ref_Nms + epoch_Nms;
    const aocs_vec3_t r = aocs_vec3_sub(aocs_vec3_sub(h_N, m->h_ref_N), m->expected_N);
    const real_t r_norm = aocs_vec3_norm(r);
    if (!(r_norm <= bound)) {
        const uint32_t i = mom_explaining_thruster(m, r, bound);
        const real_t mean_nm = r_norm / span_s;
        if (i < AOCS_MOM_THRUSTERS_MAX) {
            if ((m->ineffective_run > 0u) && (m->suspect == i)) {
                m->ineffective_run = aocs_fdir_count_up(m->ineffective_run);
            } else {
                m->ineffective_run = 1u; /* a first window, or another thruster than the last one */
            }
            m->suspect = i;
            m->inconsistent_run = 0u;
            if (m->ineffective_run == f->cfg.mom_persist) {
                (void)aocs_evlog_raise(&f->log, AOCS_EVT_THRUSTER_INEFFECTIVE, in->t_ns, (int32_t)i, mean_nm,
                                       f->cfg.mom_residual_nm);
                aocs_mom_t *const mom = in->mom; /* the stage fault management may reconfigure (fdir.h) */
                if (aocs_mom_thr_exclude(mom, i) == AOCS_OK) {
                    (void)aocs_evlog_raise(&f->log, AOCS_EVT_UNLOAD_ACTUATOR_SWITCHED, in->t_ns, (int32_t)i, mean_nm,
                                           f->cfg.mom_residual_nm);
                }
                m->ineffective_run = 0u;
            }
        } else {
            m->ineffective_run = 0u;
            m->inconsistent_run = aocs_fdir_count_up(m->inconsistent_run);
            if (m->inconsistent_run == f->cfg.mom_persist) {
                (void)aocs_evlog_raise(&f->log, AOCS_EVT_MOMENTUM_INCONSISTENT, in->t_ns, AOCS_EVT_UNIT_NONE, mean_nm,
                                       f->cfg.mom_residual_nm);
            }
        }
    } else {
        m->ineffective_run = 0u;
        m->inconsistent_run = 0u;
        aocs_fdir_latch_confirm(f, in);
    }
}

/* This step's thruster commands, fired over the period that starts now, into the open window and the
 * stuck-open test's last period. */
static void mom_add_commands(aocs_fdir_mom_t *m, const aocs_mom_t *mom, aocs_mat3_t a_NB)
{
    m->a_prev_NB = a_NB;
    m->c_prev_N = aocs_vec3_zero();
    for (uint32_t i = 0u; i < AOCS_MOM_THRUSTERS_MAX; ++i) {
        m->on_prev_s[i] = AOCS_R(0.0);
    }
    if (mom->id == AOCS_MOM_THRUSTERS) {
        for (uint32_t i = 0u; (i < mom->cfg.thr_count) && (i < AOCS_MOM_THRUSTERS_MAX); ++i) {
            const real_t t_on = mom->out.thruster_on_s[i];
            if (t_on > AOCS_R(0.0)) {
                const aocs_vec3_t c = aocs_mat3_mul_vec(a_NB, aocs_vec3_scale(aocs_mom_thr_torque_B(mom, i), t_on));
                m->thr_impulse_N[i] = aocs_vec3_add(m->thr_impulse_N[i], c);
                m->expected_N = aocs_vec3_add(m->expected_N, c);
                m->c_prev_N = aocs_vec3_add(m->c_prev_N, c);
                m->on_prev_s[i] = t_on;
            }
        }
    }
    m->periods = aocs_fdir_count_up(m->periods);
}

void aocs_fdir_mom_step(aocs_fdir_t *f, const aocs_fdir_input_t *in, const aocs_wheels_t *wheels)
{
    aocs_fdir_mom_t *m = &f->mom;
    const aocs_det_output_t *est = in->est;
    aocs_vec3_t hw_B = aocs_vec3_zero();
    aocs_vec3_t h_B = aocs_vec3_zero();
    int usable = 0;
    if ((f->cfg.mom_residual_nm > AOCS_R(0.0)) && (wheels != NULL) && (wheels->initialised != 0) &&
        (in->wheel_speed_radps != NULL) && (est != NULL) && (est->status == AOCS_OK) && (in->mom != NULL) &&
        (in->period_s > AOCS_R(0.0)) && (f->replan == 0) && (f->wheels_before.initialised == 0)) {
        /* H = J w + h_w (docs/spec.md 5.3), the wheels' share computed once: it also gives the epoch term. A
         * tachometer speed not finite or beyond its range leaves the momentum unknown (aocs_wheels_h_B would
         * give it as zero): the sample is no window's */
        if (aocs_wheels_check_speeds(wheels, in->wheel_speed_radps) == AOCS_OK) {
            hw_B = aocs_wheels_h_B(wheels, in->wheel_speed_radps);
            h_B = aocs_vec3_add(aocs_mat3_mul_vec(wheels->cfg.inertia_B_kgm2, est->w_BN_B), hw_B);
            if (aocs_vec3_is_finite(h_B) != 0) {
                usable = 1;
            }
        }
    }
    if (usable != 0) {
        if (m->have_hw_prev == 0) {
            m->open = 0; /* the epoch uncertainty needs the last sample's wheel momentum */
        } else {
            const real_t epoch_Nms = AOCS_R(0.5) * aocs_vec3_norm(aocs_vec3_sub(hw_B, m->hw_prev_B));
            const aocs_mat3_t a_NB = aocs_mat3_transpose(aocs_quat_to_dcm(est->q_BN));
            const aocs_vec3_t h_N = aocs_mat3_mul_vec(a_NB, h_B);
            /* the last period alone, for the stuck-open test: its residual and bound (docs/spec.md 5.15.8) */
            int moved = 0;
            if (m->have_period != 0) {
                moved = aocs_fdir_open_test(f, in, aocs_vec3_sub(aocs_vec3_sub(h_N, m->h_prev_N), m->c_prev_N),
                                            (f->cfg.mom_residual_nm * in->period_s) + m->epoch_prev_Nms + epoch_Nms);
            }
            if ((m->open == 0) || (moved != 0)) {
                mom_open(m, h_N, epoch_Nms); /* a first window, or a latch valve moved: a new window from now */
            } else if (m->periods >= f->cfg.mom_window) {
                mom_judge(f, in, h_N, epoch_Nms);
                mom_open(m, h_N, epoch_Nms);
            } else {
                /* the window goes on */
            }
            mom_add_commands(m, in->mom, a_NB);
            m->h_prev_N = h_N;
            m->epoch_prev_Nms = epoch_Nms;
            m->have_period = 1;
        }
        m->hw_prev_B = hw_B;
        m->have_hw_prev = 1;
    } else {
        m->open = 0; /* a step without a usable momentum: the next window starts afresh */
        m->have_hw_prev = 0;
        m->have_period = 0;
    }
}
