/*
 * The fixed-rate executive: config validation, run-time selection, and the
 * control step (check inputs, choose the mode, run the law, saturate, time).
 * Mode rules are documented in aocs/executive.h.
 */
#include <stddef.h>
#include <string.h>

#include "aocs/config_registry.h"
#include "aocs/hal.h"
#include "exec_internal.h"

const char *aocs_exec_mode_name(aocs_exec_mode_t mode)
{
    const char *name = "unknown";
    if (mode == AOCS_EXEC_MODE_STANDBY) {
        name = "standby";
    } else if (mode == AOCS_EXEC_MODE_NOMINAL) {
        name = "nominal";
    } else if (mode == AOCS_EXEC_MODE_SAFE) {
        name = "safe";
    } else {
        name = "unknown";
    }
    return name;
}

void aocs_exec_config_default(aocs_exec_config_t *cfg)
{
    if (cfg != NULL) {
        (void)memset(cfg, 0, sizeof(*cfg));
        /* every one-value field's DEFAULT column (config_fields.def); law NONE, guidance STEP with the
         * bang-coast-bang profile, no limit, no inertia: the zero of their members */
        aocs_config_apply_defaults(cfg);
        cfg->target.qd_DN = aocs_quat_identity();
        /* no wheel array (n = 0), and the array's own defaults (friction width, no null-space management) for
         * an adapter that fills only the keys it was given */
        aocs_wheels_config_default(&cfg->wheels);
        cfg->wheels.inertia_B_kgm2 = aocs_mat3_zero();
    }
}

/* 1 when any component of the target rotation rate is non-zero (exact test, no tolerance) */
static int rate_is_nonzero(aocs_vec3_t w)
{
    int nonzero = 0;
    for (int i = 0; i < 3; ++i) {
        if ((w.v[i] > AOCS_R(0.0)) || (w.v[i] < AOCS_R(0.0))) {
            nonzero = 1;
        }
    }
    return nonzero;
}

/*
 * A rotating target brings its own wd and wd_dot (guidance.c): a fixed
 * wd/wd_dot given as well would be ambiguous, so it is rejected.
 */
static aocs_status_t rotating_target_check(const aocs_exec_target_t *target, int rotating)
{
    aocs_status_t st = AOCS_OK;
    if ((rotating != 0) && ((rate_is_nonzero(target->wd_B) != 0) || (rate_is_nonzero(target->wd_dot_B) != 0))) {
        st = AOCS_ERR_TARGET_INVALID;
    }
    return st;
}

/* 1 in guidance mode SLEW (a commanded target starts a slew) */
static int slew_mode(const aocs_exec_config_t *cfg)
{
    return ((cfg->guidance.mode == AOCS_GUIDANCE_MODE_SLEW) ? 1 : 0);
}

/* Guidance config (aocs_exec_init): the mode, and in SLEW mode a fixed target and a valid slew config. */
static aocs_status_t guidance_config_check(const aocs_exec_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (((int)cfg->guidance.mode < 0) || (cfg->guidance.mode >= AOCS_GUIDANCE_MODE_COUNT)) {
        st = AOCS_ERR_GUIDANCE_MODE_INVALID;
    } else if (slew_mode(cfg) == 0) {
        st = AOCS_OK; /* STEP: the slew fields are not used */
    } else if ((rate_is_nonzero(cfg->target_rotation_rate_D) != 0) ||
               (rotating_target_check(&cfg->target, 1) != AOCS_OK)) {
        st = AOCS_ERR_GUIDANCE_TARGET_MOVING;
    } else {
        st = aocs_slew_config_check(&cfg->guidance.slew);
    }
    return st;
}

static aocs_status_t config_check(const aocs_exec_config_t *cfg, uint64_t *period_ns)
{
    aocs_status_t st = aocs_exec_period_to_ns(cfg->period_s, period_ns);
    if (st != AOCS_OK) {
        /* period_to_ns already says RATE_INVALID */
    } else if (((int)cfg->law < 0) || (cfg->law >= AOCS_LAW_COUNT)) {
        st = AOCS_ERR_UNKNOWN_LAW;
    } else if ((cfg->clock != AOCS_EXEC_CLOCK_LOCKSTEP) && (cfg->clock != AOCS_EXEC_CLOCK_REALTIME)) {
        st = AOCS_ERR_MODE_INVALID;
    } else if ((aocs_exec_target_check(&cfg->target) != AOCS_OK) ||
               (aocs_vec3_is_finite(cfg->target_rotation_rate_D) == 0) ||
               (rotating_target_check(&cfg->target, rate_is_nonzero(cfg->target_rotation_rate_D)) != AOCS_OK)) {
        st = AOCS_ERR_TARGET_INVALID;
    } else if (!AOCS_IS_FINITE(cfg->k_safe)) {
        st = AOCS_ERR_PARAM_NOT_FINITE;
    } else if (!(cfg->k_safe > AOCS_R(0.0))) {
        st = AOCS_ERR_GAIN_NOT_POSITIVE;
    } else if ((cfg->recover_good_samples == 0u) || (cfg->missing_max_periods == 0u)) {
        st = AOCS_ERR_GAIN_NOT_POSITIVE;
    } else if ((cfg->clock == AOCS_EXEC_CLOCK_REALTIME) && (cfg->stale_timeout_ns == 0u)) {
        st = AOCS_ERR_GAIN_NOT_POSITIVE;
    } else {
        st = aocs_exec_limits_check(cfg);
    }
    if (st == AOCS_OK) {
        st = guidance_config_check(cfg);
    }
    return st;
}

/* Re-runs the selected law's init from the cached config (the reset of a stateful law); no-op for NONE. */
static void law_reset(aocs_exec_t *exec)
{
    if (exec->law != AOCS_LAW_NONE) {
        /* the same config passed this init before: it cannot fail now */
        (void)aocs_exec_law_init(&exec->states, &exec->cfg.laws, exec->law);
    }
}

static void set_mode(aocs_exec_t *exec, aocs_exec_mode_t mode)
{
    if (exec->mode != mode) {
        exec->mode = mode;
        aocs_exec_count(&exec->counters.mode_transitions, 1u);
    }
    exec->good_run = 0u;
}

aocs_status_t aocs_exec_init(aocs_exec_t *exec, const aocs_exec_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    uint64_t period_ns = 0u;
    if (exec != NULL) {
        /* any failure below leaves exec cleanly not initialised */
        (void)memset(exec, 0, sizeof(*exec));
        exec->initialised = 0;
    }
    if ((exec == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        st = config_check(cfg, &period_ns);
        if (st == AOCS_OK) {
            st = aocs_exec_wheels_init(exec, cfg);
        }
        if ((st == AOCS_OK) && (cfg->law != AOCS_LAW_NONE)) {
            st = aocs_exec_law_init(&exec->states, &cfg->laws, cfg->law);
        }
        if (st == AOCS_OK) {
            exec->cfg = *cfg;
            exec->period_ns = period_ns;
            exec->law = cfg->law;
            exec->target = cfg->target;
            exec->target_t0_ns = cfg->target_t0_ns;
            exec->target_rotating = rate_is_nonzero(cfg->target_rotation_rate_D);
            exec->slew_pending = slew_mode(cfg);
            exec->requested = (cfg->law == AOCS_LAW_NONE) ? AOCS_EXEC_MODE_STANDBY : AOCS_EXEC_MODE_NOMINAL;
            exec->mode = exec->requested;
            exec->last_u_cmd = aocs_vec3_zero();
            exec->initialised = 1;
        }
    }
    return st;
}

/* AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED, or AOCS_OK when exec can take a command */
static aocs_status_t exec_ready(const aocs_exec_t *exec)
{
    aocs_status_t st = AOCS_OK;
    if (exec == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (exec->initialised == 0) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        st = AOCS_OK;
    }
    return st;
}

aocs_status_t aocs_exec_select(aocs_exec_t *exec, aocs_law_id_t law, const aocs_exec_target_t *target)
{
    aocs_status_t st = exec_ready(exec);
    if (st == AOCS_OK) {
        /* a rotating target or a slew brings its own wd / wd_dot: a fixed one given too is ambiguous */
        int moving_forbidden = 0;
        if ((exec->target_rotating != 0) || (slew_mode(&exec->cfg) != 0)) {
            moving_forbidden = 1;
        }
        if (((int)law < 0) || (law >= AOCS_LAW_COUNT)) {
            st = AOCS_ERR_UNKNOWN_LAW;
        } else if ((target != NULL) &&
                   ((aocs_exec_target_check(target) != AOCS_OK) ||
                    (rotating_target_check(target, moving_forbidden) != AOCS_OK))) {
            st = AOCS_ERR_TARGET_INVALID;
        } else if ((law != AOCS_LAW_NONE) && (law != exec->law)) {
            /* one state per law: a failing init leaves the active law untouched */
            st = aocs_exec_law_init(&exec->states, &exec->cfg.laws, law);
        } else {
            st = AOCS_OK;
        }
        if (st == AOCS_OK) {
            int from_standby = 0;
            if (exec->mode == AOCS_EXEC_MODE_STANDBY) {
                from_standby = 1;
            }
            if (target != NULL) {
                exec->target = *target;
                exec->slew_pending = slew_mode(&exec->cfg); /* SLEW: flown from the next good sample */
                if (exec->have_sample != 0) {
                    /* the commanded attitude is the target now: the time of the last sample */
                    exec->target_t0_ns = exec->last_t_sensor_ns;
                }
            }
            if (law != exec->law) {
                /* good samples seen with the previous law prove nothing about this one */
                exec->good_run = 0u;
            }
            exec->law = law;
            if (law == AOCS_LAW_NONE) {
                exec->requested = AOCS_EXEC_MODE_STANDBY;
                set_mode(exec, AOCS_EXEC_MODE_STANDBY);
            } else {
                exec->requested = AOCS_EXEC_MODE_NOMINAL;
                if (exec->mode == AOCS_EXEC_MODE_STANDBY) {
                    set_mode(exec, AOCS_EXEC_MODE_NOMINAL);
                }
                /* from SAFE: only the recovery rule returns to NOMINAL */
            }
            if ((target != NULL) || ((from_standby != 0) && (exec->mode == AOCS_EXEC_MODE_NOMINAL))) {
                law_reset(exec); /* target change or entry into NOMINAL: the law's state starts afresh */
            }
            aocs_exec_count(&exec->counters.select_accepted, 1u);
        } else {
            aocs_exec_count(&exec->counters.select_rejected, 1u);
        }
    }
    return st;
}

/*
 * 1 when sample (tick, t) continues the sample (ref_tick, ref_t): the tick
 * advances by g in [1, G] (modulo 2^32: the counter may wrap) and the time
 * advances, in lockstep by g periods within T / AOCS_EXEC_LOCKSTEP_TOL_DIV
 * (executive.h, "Frame acceptance"). *gap_out = g. Unsigned arithmetic only:
 * g T <= 1024 * 1e12 ns, no wrap.
 */
static int sample_continues(const aocs_exec_t *exec, uint32_t ref_tick, uint64_t ref_t_ns, uint32_t tick,
                            uint64_t t_ns, uint32_t *gap_out)
{
    int ok = 0;
    const uint32_t gap = tick - ref_tick;
    *gap_out = gap;
    if ((gap >= 1u) && (gap <= AOCS_EXEC_TICK_JUMP_MAX) && (t_ns > ref_t_ns)) {
        if (exec->cfg.clock == AOCS_EXEC_CLOCK_LOCKSTEP) {
            const uint64_t dt = t_ns - ref_t_ns;
            const uint64_t expected = (uint64_t)gap * exec->period_ns;
            const uint64_t tol = exec->period_ns / (uint64_t)AOCS_EXEC_LOCKSTEP_TOL_DIV;
            uint64_t err = 0u;
            if (dt >= expected) {
                err = dt - expected;
            } else {
                err = expected - dt;
            }
            if (err <= tol) {
                ok = 1;
            }
        } else {
            ok = 1;
        }
    }
    return ok;
}

/* Real time: 1 when t lies on the HAL clock within [now - stale_timeout, now + T]. */
static int sample_on_hal_clock(const aocs_exec_t *exec, uint64_t t_ns)
{
    const uint64_t now = aocs_hal_time_ns();
    int ok = 1;
    if ((now > t_ns) && ((now - t_ns) > exec->cfg.stale_timeout_ns)) {
        ok = 0; /* too old */
    } else if ((t_ns > now) && ((t_ns - now) > exec->period_ns)) {
        ok = 0; /* from the future: no clock the adapter reads runs ahead of ours by a period */
    } else {
        ok = 1;
    }
    return ok;
}

static void take_reference(aocs_exec_t *exec, const aocs_exec_input_t *in)
{
    exec->have_sample = 1;
    exec->last_tick = in->tick;
    exec->last_t_sensor_ns = in->t_sensor_ns;
    exec->resync_run = 0u;
}

/*
 * A sample that does not continue the reference: one more resynchronisation
 * candidate. Returns 1 when it completes K consecutive candidates (each
 * continuing the one before): the caller then takes it as the reference.
 */
static int resync_candidate(aocs_exec_t *exec, const aocs_exec_input_t *in)
{
    uint32_t gap = 0u;
    int resync = 0;
    if ((exec->resync_run > 0u) &&
        (sample_continues(exec, exec->resync_tick, exec->resync_t_ns, in->tick, in->t_sensor_ns, &gap) != 0)) {
        exec->resync_run += 1u;
    } else {
        exec->resync_run = 1u;
    }
    exec->resync_tick = in->tick;
    exec->resync_t_ns = in->t_sensor_ns;
    if (exec->resync_run >= AOCS_EXEC_RESYNC_FRAMES) {
        resync = 1;
    }
    return resync;
}

/*
 * Frame acceptance (executive.h, "Frame acceptance"): a sample is fresh when
 * it continues the tick/time reference (a tick gap counts the samples that
 * never came), or when it completes a resynchronisation; otherwise it is
 * stale and the reference does not move, so no single sample, however far
 * its tick or time, can make the later good ones stale.
 */
static aocs_status_t sample_timing_check(aocs_exec_t *exec, const aocs_exec_input_t *in)
{
    aocs_status_t st = AOCS_OK;
    uint32_t gap = 0u;
    if ((exec->cfg.clock == AOCS_EXEC_CLOCK_REALTIME) && (sample_on_hal_clock(exec, in->t_sensor_ns) == 0)) {
        /* the HAL clock is the authority in real time: such a sample is no candidate either */
        st = AOCS_ERR_INPUT_STALE;
        exec->resync_run = 0u;
    } else if (exec->have_sample == 0) {
        take_reference(exec, in);
    } else if (sample_continues(exec, exec->last_tick, exec->last_t_sensor_ns, in->tick, in->t_sensor_ns, &gap) !=
               0) {
        if (gap > 1u) {
            /* periods already reported by step_no_input are not counted twice */
            if ((gap - 1u) > exec->missing_run) {
                aocs_exec_count(&exec->counters.missing, (gap - 1u) - exec->missing_run);
            }
            if ((gap - 1u) >= exec->cfg.missing_max_periods) {
                st = AOCS_ERR_INPUT_MISSING;
            }
        }
        take_reference(exec, in);
    } else if (resync_candidate(exec, in) != 0) {
        take_reference(exec, in);
        aocs_exec_count(&exec->resyncs, 1u);
    } else {
        st = AOCS_ERR_INPUT_STALE;
    }
    return st;
}

static void finish_output(aocs_exec_t *exec, aocs_exec_output_t *out, uint64_t budget)
{
    out->law = exec->law;
    out->mode = exec->mode;
    out->budget_ns = budget;
    out->overrun = 0;
    if (out->step_time_ns > budget) {
        out->overrun = 1;
        aocs_exec_count(&exec->counters.overrun, 1u);
    }
    if (out->step_time_ns > exec->counters.step_time_max_ns) {
        exec->counters.step_time_max_ns = out->step_time_ns;
    }
    if (out->saturated != 0) {
        aocs_exec_count(&exec->counters.saturated, 1u);
    }
    aocs_exec_count(&exec->counters.steps, 1u);
    exec->last_u_cmd = out->u_cmd;
    out->counters = exec->counters;
}

static void zero_output(aocs_exec_output_t *out)
{
    (void)memset(out, 0, sizeof(*out));
    out->u_cmd = aocs_vec3_zero();
    out->u_unsat = aocs_vec3_zero();
    out->law = AOCS_LAW_NONE;
    out->mode = AOCS_EXEC_MODE_STANDBY;
    out->law_status = AOCS_OK;
    out->input_status = AOCS_OK;
}

static uint64_t step_budget(const aocs_exec_t *exec)
{
    uint64_t budget = exec->cfg.budget_ns;
    if (budget == 0u) {
        budget = (exec->mode == AOCS_EXEC_MODE_NOMINAL) ? aocs_law_budget_ns(exec->law)
                                                        : (uint64_t)AOCS_EXEC_SAFE_BUDGET_NS;
        if ((exec->mode == AOCS_EXEC_MODE_NOMINAL) && (slew_mode(&exec->cfg) != 0) &&
            (aocs_law_is_orbit(exec->law) == 0)) {
            budget += (uint64_t)AOCS_EXEC_SLEW_BUDGET_NS; /* the slew reference and feedforward */
        }
    }
    return budget;
}

/*
 * The target the law sees this step: the stored one, or for a rotating
 * target qd(t) from the sensor time and, on a usable sample, wd_B and
 * wd_dot_B from the measured attitude and rate (guidance.c).
 */
static aocs_exec_target_t slew_target(aocs_exec_t *exec, const aocs_exec_input_t *in, aocs_status_t in_st)
{
    aocs_exec_target_t target = exec->target;
    if ((exec->slew_pending != 0) && (in_st == AOCS_OK) && (exec->law != AOCS_LAW_NONE)) {
        aocs_slew_envelope_t env;
        env.u_max_axis_Nm = exec->cfg.u_max_axis;
        env.u_max_norm_Nm = exec->cfg.u_max_norm;
        env.wheels = (exec->wheels.initialised != 0) ? &exec->wheels : NULL;
        /* config, limits and target were validated: a failure leaves a zero-length slew at the target */
        (void)aocs_slew_plan(&exec->slew, &exec->cfg.guidance.slew, &env, in->q_BN, exec->target.qd_DN);
        exec->slew_t0_ns = in->t_sensor_ns;
        exec->slew_pending = 0;
    }
    if (exec->slew_pending == 0) {
        aocs_slew_ref_t ref;
        aocs_slew_eval(&exec->slew, aocs_exec_elapsed_s(in->t_sensor_ns, exec->slew_t0_ns), &ref);
        target.qd_DN = ref.qd_DN;
        target.wd_B = aocs_vec3_zero();
        target.wd_dot_B = aocs_vec3_zero();
        if (in_st == AOCS_OK) {
            aocs_exec_slew_rates(in->q_BN, ref.qd_DN, ref.wd_D, ref.wd_dot_D, in->w_BN_B, &target.wd_B,
                                 &target.wd_dot_B);
        }
    }
    return target;
}

static aocs_exec_target_t guidance_target(aocs_exec_t *exec, const aocs_exec_input_t *in, aocs_status_t in_st)
{
    aocs_exec_target_t target = exec->target;
    if ((slew_mode(&exec->cfg) != 0) && (aocs_law_is_orbit(exec->law) == 0)) {
        target = slew_target(exec, in, in_st);
    } else if ((exec->target_rotating != 0) && (aocs_law_is_orbit(exec->law) == 0)) {
        const aocs_vec3_t w_D = exec->cfg.target_rotation_rate_D;
        target.qd_DN = aocs_exec_guidance_attitude(exec->target.qd_DN, w_D,
                                                   aocs_exec_elapsed_s(in->t_sensor_ns, exec->target_t0_ns));
        target.wd_B = aocs_vec3_zero();
        target.wd_dot_B = aocs_vec3_zero();
        if (in_st == AOCS_OK) {
            aocs_exec_guidance_rates(in->q_BN, target.qd_DN, w_D, in->w_BN_B, &target.wd_B, &target.wd_dot_B);
        }
    } else {
        /* fixed target, step mode: the commanded target as it is */
    }
    return target;
}

aocs_status_t aocs_exec_step(aocs_exec_t *exec, const aocs_exec_input_t *in, aocs_exec_output_t *out)
{
    aocs_status_t st = AOCS_OK;
    if (out != NULL) {
        zero_output(out);
    }
    if ((exec == NULL) || (in == NULL) || (out == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (exec->initialised == 0) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        aocs_status_t in_st;
        aocs_status_t law_st = AOCS_OK;
        aocs_vec3_t u_law = aocs_vec3_zero();
        aocs_att_input_t att;
        aocs_orbit_input_t orbit;
        aocs_exec_target_t target;
        uint64_t t_start;
        uint32_t c_start;
        int good;
        int sat = 0;

        out->tick = in->tick;
        in_st = sample_timing_check(exec, in);
        if (in_st == AOCS_OK) {
            in_st = aocs_exec_input_check(exec->law, in);
        }
        if ((in_st == AOCS_ERR_INPUT_NOT_FINITE) || (in_st == AOCS_ERR_QUAT_NOT_UNIT) ||
            (in_st == AOCS_ERR_INPUT_INVALID)) {
            aocs_exec_count(&exec->counters.invalid, 1u);
        } else if (in_st == AOCS_ERR_INPUT_STALE) {
            aocs_exec_count(&exec->counters.stale, 1u);
        } else {
            /* missing samples were counted by the timing check, OK needs nothing */
        }

        t_start = aocs_hal_time_ns();
        c_start = aocs_hal_cycles();
        target = guidance_target(exec, in, in_st);
        att.q_BN = in->q_BN;
        att.w_BN_B = in->w_BN_B;
        att.qd_DN = target.qd_DN;
        att.wd_B = target.wd_B;
        att.wd_dot_B = target.wd_dot_B;
        att.dt_s = exec->cfg.period_s;
        att.u_max_axis = exec->cfg.u_max_axis;
        att.u_max_norm = exec->cfg.u_max_norm;
        orbit.pos_m = in->pos_m;
        orbit.vel_mps = in->vel_mps;
        orbit.dt_s = exec->cfg.period_s;

        /* a good sample now completes the recovery (if the law works): enter NOMINAL with a fresh law state */
        if ((in_st == AOCS_OK) && (exec->mode == AOCS_EXEC_MODE_SAFE) &&
            (exec->requested == AOCS_EXEC_MODE_NOMINAL) &&
            (exec->good_run >= (exec->cfg.recover_good_samples - 1u))) {
            law_reset(exec);
        }
        /* the law also runs in SAFE (output unused) so recovery needs a law that works */
        if ((in_st == AOCS_OK) && (exec->law != AOCS_LAW_NONE)) {
            law_st = aocs_exec_law_step(&exec->states, exec->law, &att, &orbit, &u_law);
            if (law_st != AOCS_OK) {
                aocs_exec_count(&exec->counters.law_error, 1u);
            }
        }
        good = 0;
        if ((in_st == AOCS_OK) && (law_st == AOCS_OK)) {
            good = 1;
        }

        if (exec->requested == AOCS_EXEC_MODE_NOMINAL) {
            if (good == 0) {
                set_mode(exec, AOCS_EXEC_MODE_SAFE);
            } else if (exec->mode == AOCS_EXEC_MODE_SAFE) {
                exec->good_run += 1u;
                if (exec->good_run >= exec->cfg.recover_good_samples) {
                    set_mode(exec, AOCS_EXEC_MODE_NOMINAL);
                }
            } else {
                /* NOMINAL and good: stay */
            }
        }

        if (exec->mode == AOCS_EXEC_MODE_NOMINAL) {
            out->u_unsat = u_law;
            if ((slew_mode(&exec->cfg) != 0) && (aocs_law_is_orbit(exec->law) == 0) &&
                (aocs_law_has_feedforward(exec->law) == 0)) {
                /* SPEC 5.1: u_ff = J wd_dot + wd x (J wd + h_wheels), h_wheels = sum Js g Omega from the
                 * tachometers (zero without a wheel array) */
                out->u_ff = aocs_slew_feedforward(exec->cfg.guidance.slew.inertia_kgm2, target.wd_B,
                                                  target.wd_dot_B,
                                                  aocs_wheels_h_B(&exec->wheels, in->wheel_speed_radps));
                out->u_unsat = aocs_vec3_add(u_law, out->u_ff);
            }
        } else if (exec->mode == AOCS_EXEC_MODE_SAFE) {
            out->u_unsat = aocs_exec_safe_command(&exec->cfg, exec->law, in);
        } else {
            out->u_unsat = aocs_vec3_zero();
        }
        out->u_cmd = aocs_exec_saturate(&exec->cfg, out->u_unsat, &sat);
        aocs_exec_wheels_apply(exec, in->wheel_speed_radps, in->w_BN_B, out, &sat);
        out->step_time_ns = aocs_hal_time_ns() - t_start;
        out->step_cycles = aocs_hal_cycles() - c_start;

        out->saturated = sat;
        out->target = target;
        out->law_status = law_st;
        out->input_status = in_st;
        finish_output(exec, out, step_budget(exec));
        if (in_st != AOCS_ERR_INPUT_STALE) {
            exec->missing_run = 0u; /* the tick reference moved past the counted periods */
        }
    }
    return st;
}

aocs_status_t aocs_exec_step_no_input(aocs_exec_t *exec, aocs_exec_output_t *out)
{
    aocs_status_t st = AOCS_OK;
    if (out != NULL) {
        zero_output(out);
    }
    if ((exec == NULL) || (out == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (exec->initialised == 0) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        uint64_t t_start = aocs_hal_time_ns();
        uint32_t c_start = aocs_hal_cycles();
        int sat = 0;
        aocs_exec_count(&exec->missing_run, 1u);
        aocs_exec_count(&exec->counters.missing, 1u);
        if (exec->mode == AOCS_EXEC_MODE_STANDBY) {
            out->u_unsat = aocs_vec3_zero();
        } else if ((exec->mode == AOCS_EXEC_MODE_NOMINAL) && (exec->missing_run < exec->cfg.missing_max_periods)) {
            /* zero-order hold of the last command over a short gap */
            out->u_unsat = exec->last_u_cmd;
        } else {
            set_mode(exec, AOCS_EXEC_MODE_SAFE);
            out->u_unsat = aocs_vec3_zero(); /* no fresh rate to damp */
        }
        out->u_cmd = aocs_exec_saturate(&exec->cfg, out->u_unsat, &sat);
        aocs_exec_wheels_apply(exec, exec->wheel_speed_last, exec->w_last_B, out, &sat);
        out->step_time_ns = aocs_hal_time_ns() - t_start;
        out->step_cycles = aocs_hal_cycles() - c_start;
        out->saturated = sat;
        out->tick = exec->last_tick;
        out->law_status = AOCS_OK;
        out->input_status = AOCS_ERR_INPUT_MISSING;
        finish_output(exec, out, step_budget(exec));
    }
    return st;
}

aocs_status_t aocs_exec_set_target_epoch(aocs_exec_t *exec, uint64_t t0_ns)
{
    aocs_status_t st = exec_ready(exec);
    if (st == AOCS_OK) {
        exec->target_t0_ns = t0_ns;
    }
    return st;
}

aocs_exec_counters_t aocs_exec_counters(const aocs_exec_t *exec)
{
    aocs_exec_counters_t c;
    if (exec != NULL) {
        c = exec->counters;
    } else {
        (void)memset(&c, 0, sizeof(c));
    }
    return c;
}
