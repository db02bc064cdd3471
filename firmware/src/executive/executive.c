/*
 * The fixed-rate executive (aocs/exec/pipeline.h): config validation,
 * run-time selection, and the control step, which sequences the stages
 * (accept the input, determine the attitude, guide, run the law, manage
 * momentum, actuate), owns the modes and times the step.
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

/*
 * A rotating target brings its own wd and wd_dot (guidance stage): a fixed
 * wd/wd_dot given as well would be ambiguous, so it is rejected.
 */
static aocs_status_t rotating_target_check(const aocs_exec_target_t *target, int rotating)
{
    aocs_status_t st = AOCS_OK;
    if ((rotating != 0) && ((aocs_guidance_vec_nonzero(target->wd_B) != 0) || (aocs_guidance_vec_nonzero(target->wd_dot_B) != 0))) {
        st = AOCS_ERR_TARGET_INVALID;
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
    } else if (((int)cfg->clock < 0) || (cfg->clock >= AOCS_EXEC_CLOCK_COUNT)) {
        st = AOCS_ERR_MODE_INVALID;
    } else if ((aocs_exec_target_check(&cfg->target) != AOCS_OK) ||
               (aocs_vec3_is_finite(cfg->target_rotation_rate_D) == 0) ||
               (rotating_target_check(&cfg->target, aocs_guidance_vec_nonzero(cfg->target_rotation_rate_D)) != AOCS_OK)) {
        st = AOCS_ERR_TARGET_INVALID;
    } else if (aocs_exec_safe_config_check(cfg) != AOCS_OK) {
        st = aocs_exec_safe_config_check(cfg);
    } else if ((cfg->recover_good_samples == 0u) || (cfg->missing_max_periods == 0u)) {
        st = AOCS_ERR_GAIN_NOT_POSITIVE;
    } else if ((cfg->clock == AOCS_EXEC_CLOCK_REALTIME) && (cfg->stale_timeout_ns == 0u)) {
        st = AOCS_ERR_GAIN_NOT_POSITIVE;
    } else {
        aocs_act_limits_t lim;
        lim.u_max_axis = cfg->u_max_axis;
        lim.u_max_norm = cfg->u_max_norm;
        st = aocs_act_limits_check(&lim);
    }
    if (st == AOCS_OK) {
        st = aocs_guidance_check(&cfg->guidance, &cfg->target, cfg->target_rotation_rate_D);
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
            st = aocs_det_init(&exec->det, &cfg->determination);
        }
        if (st == AOCS_OK) {
            st = aocs_mom_init(&exec->momentum, &cfg->momentum);
        }
        if (st == AOCS_OK) {
            st = aocs_act_init(&exec->act, cfg);
        }
        if (st == AOCS_OK) {
            st = aocs_fdir_init(&exec->fdir, &cfg->fdir);
        }
        if ((st == AOCS_OK) && (cfg->law != AOCS_LAW_NONE)) {
            st = aocs_exec_law_init(&exec->states, &cfg->laws, cfg->law);
        }
        if (st == AOCS_OK) {
            exec->cfg = *cfg;
            exec->period_ns = period_ns;
            exec->law = cfg->law;
            aocs_accept_init(&exec->accept, cfg->clock, period_ns, cfg->stale_timeout_ns, cfg->missing_max_periods,
                             aocs_det_needs(exec->det.id));
            aocs_guidance_init(&exec->guidance, &cfg->guidance, &cfg->target, cfg->target_rotation_rate_D,
                               cfg->target_t0_ns, cfg->u_max_axis, cfg->u_max_norm);
            exec->requested = (cfg->law == AOCS_LAW_NONE) ? AOCS_EXEC_MODE_STANDBY : AOCS_EXEC_MODE_NOMINAL;
            exec->mode = exec->requested;
            exec->last_u_cmd = aocs_vec3_zero();
            exec->gyroless_capable = 0;
            if ((aocs_det_gyroless_capable(&exec->det) != 0u) &&
                (aocs_mat3_check_inertia(cfg->guidance.slew.inertia_kgm2) == AOCS_OK)) {
                exec->gyroless_capable = 1;
            }
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
        const int moving_forbidden = aocs_guidance_owns_rates(&exec->guidance);
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
                aocs_guidance_command(&exec->guidance, target, exec->accept.have_sample,
                                      exec->accept.last_t_sensor_ns);
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
        if ((exec->mode == AOCS_EXEC_MODE_NOMINAL) && (aocs_law_is_orbit(exec->law) == 0)) {
            budget += aocs_guidance_budget_ns(&exec->guidance); /* e.g. the slew reference and feedforward */
        }
        budget += aocs_det_budget_ns(&exec->det); /* the estimator runs in every mode */
        budget += aocs_mom_budget_ns(&exec->momentum); /* so does the momentum stage */
        if (exec->fdir.cfg.enabled != 0u) {
            budget += (uint64_t)AOCS_EXEC_FDIR_BUDGET_NS; /* and fault management */
        }
    }
    return budget;
}

/* The target an attitude law sees (guidance stage); orbit laws regulate to zero and see the stored target. */
static void guide(aocs_exec_t *exec, const aocs_exec_input_t *in, const aocs_det_output_t *est,
                  aocs_exec_target_t *target)
{
    if (aocs_law_is_orbit(exec->law) == 0) {
        aocs_guidance_input_t gin;
        gin.t_ns = in->t_sensor_ns;
        gin.est = est;
        gin.usable = 0;
        if (est->status == AOCS_OK) {
            gin.usable = 1;
        }
        gin.law_active = 0;
        if (exec->law != AOCS_LAW_NONE) {
            gin.law_active = 1;
        }
        gin.wheels = aocs_act_wheels(&exec->act);
        aocs_guidance_step(&exec->guidance, &gin, target);
    } else {
        *target = exec->guidance.target;
    }
}

/* The momentum-management stage's step: the wheels' momentum from the tachometers (valid with an array whose
 * speeds are all finite), the magnetometer, enabled while NOMINAL with an attitude law. Policy NONE costs
 * nothing: its output is the zero of zero_output (no unloading torque to take off the wheels). */
static void manage_momentum(aocs_exec_t *exec, const aocs_exec_input_t *in)
{
    aocs_mom_input_t mi;
    if (exec->momentum.id != AOCS_MOM_NONE) {
        mi.h_valid = 0;
        mi.b_valid = 0;
        mi.enabled = 0;
        if (exec->cfg.wheels.n > 0u) {
            mi.h_valid = 1;
        }
        for (uint32_t i = 0u; (i < exec->cfg.wheels.n) && (i < AOCS_WHEELS_MAX); ++i) {
            if (!AOCS_IS_FINITE(in->wheel_speed_radps[i])) {
                mi.h_valid = 0;
            }
        }
        mi.h_wheels_B_Nms = (mi.h_valid != 0) ? aocs_wheels_h_B(&exec->act.wheels, in->wheel_speed_radps) : aocs_vec3_zero();
        mi.b_B_T = in->mag_B_T;
        if (((in->valid & AOCS_EXEC_VALID_MAG) != 0u) && (aocs_vec3_is_finite(in->mag_B_T) != 0)) {
            mi.b_valid = 1;
        }
        if ((exec->mode == AOCS_EXEC_MODE_NOMINAL) && (exec->law != AOCS_LAW_NONE) && (aocs_law_is_orbit(exec->law) == 0)) {
            mi.enabled = 1;
        }
        mi.dt_s = exec->cfg.period_s;
        (void)aocs_mom_step(&exec->momentum, &mi);
    }
}

/* The fault-management stage's step (docs/spec.md 5.15), last in the pipeline: its monitors see this step's
 * sample, estimate and wheel commands. Its decisions: a wheel isolated (the array re-initialised in place)
 * replans a slew in progress on the wheels left; the tracker's exclusion applies to the next step's
 * determination; a latched SAFE holds the mode (update_mode). */
static void manage_faults(aocs_exec_t *exec, const aocs_exec_input_t *in, aocs_status_t in_st, uint32_t missing,
                          const aocs_exec_output_t *out)
{
    if (exec->fdir.cfg.enabled != 0u) {
        aocs_fdir_input_t fi;
        const int wheels = aocs_act_has_wheels(&exec->act);
        (void)memset(&fi, 0, sizeof(fi));
        fi.period_s = exec->cfg.period_s;
        fi.mode = exec->mode;
        fi.input_status = in_st;
        fi.missing = missing;
        if (in != NULL) {
            fi.t_ns = in->t_sensor_ns;
            fi.have_sample = 1;
            if (wheels != 0) {
                fi.wheel_speed_radps = in->wheel_speed_radps;
            }
            fi.gyro_w_B = in->gyro_w_B;
            if (((in->valid & AOCS_EXEC_VALID_GYRO) != 0u) && (exec->fdir.gyro.excluded == 0)) {
                fi.gyro_valid = 1; /* an excluded gyro is shown to no monitor */
            }
            fi.st_q_SN = in->st_q_SN;
            if ((in->valid & AOCS_EXEC_VALID_ST) != 0u) {
                fi.st_valid = 1;
            }
        } else {
            fi.t_ns = exec->accept.last_t_sensor_ns;
        }
        fi.est = &out->estimate;
        if (aocs_det_is_gyroless(&exec->det) == 0u) {
            fi.gyro_rrw_radps1p5 = aocs_det_gyro_rrw(&exec->det); /* gyroless: no bias state to test */
        }
        fi.gyroless_capable = exec->gyroless_capable;
        fi.alloc = (wheels != 0) ? &out->wheels : NULL;
        fi.wheels_status = out->wheels_status;
        fi.mom = (exec->momentum.id != AOCS_MOM_NONE) ? &exec->momentum : NULL;
        aocs_fdir_step(&exec->fdir, &fi, (wheels != 0) ? &exec->act.wheels : NULL);
        if (exec->fdir.replan != 0) {
            /* the slew in progress slows to the envelope left along its eigenaxis (docs/spec.md 5.15.2) */
            const real_t a_old = aocs_wheels_alpha_max(&exec->fdir.wheels_before, exec->cfg.guidance.slew.inertia_kgm2,
                                                       exec->guidance.slew.e);
            const real_t a_new = aocs_wheels_alpha_max(&exec->act.wheels, exec->cfg.guidance.slew.inertia_kgm2,
                                                       exec->guidance.slew.e);
            if ((a_old > AOCS_R(0.0)) && (a_new < a_old)) {
                aocs_guidance_slow_down(&exec->guidance, fi.t_ns, AOCS_SQRT(a_new / a_old));
            }
        }
        aocs_det_set_st_excluded(&exec->det, (exec->fdir.st.excluded != 0) ? 1u : 0u);
        if (exec->fdir.st_rescaled != 0) {
            aocs_det_set_st_noise_scale(&exec->det, exec->fdir.st.noise_scale); /* the tracker's noise (5.15.3) */
        }
        if (exec->fdir.reinflate_bias != 0) {
            aocs_det_reinflate_bias(&exec->det); /* a gyro bias jump: re-estimated from its prior (5.15.4) */
        }
        if (exec->fdir.go_gyroless != 0) {
            /* the gyro excluded: the estimator propagates on the dynamics (5.6.12), and a sample no longer
             * needs the gyro's flag to be accepted */
            if (aocs_det_set_gyroless(&exec->det, &exec->cfg.guidance.slew.inertia_kgm2) == AOCS_OK) {
                exec->accept.needs &= ~AOCS_EXEC_VALID_GYRO;
            } else {
                exec->fdir.safe_latched = 1;
            }
        }
    }
}

/* A gyroless estimator (docs/spec.md 5.6.12) propagates over the coming period with the body torque commanded
 * now, the wheels' (u_cmd) plus a thruster or magnetorquer unload's, and the wheels' momentum measured now. */
static void gyroless_torque(aocs_exec_t *exec, const aocs_exec_input_t *in, const aocs_exec_output_t *out)
{
    if (aocs_det_is_gyroless(&exec->det) != 0u) {
        aocs_vec3_t tau = out->u_cmd;
        aocs_vec3_t h = aocs_vec3_zero();
        if ((exec->momentum.id != AOCS_MOM_NONE) && (exec->mode == AOCS_EXEC_MODE_NOMINAL)) {
            tau = aocs_vec3_add(tau, exec->momentum.out.u_unload_B_Nm);
        }
        if (aocs_act_has_wheels(&exec->act) != 0) {
            h = aocs_wheels_h_B(&exec->act.wheels, in->wheel_speed_radps);
        }
        aocs_det_set_torque(&exec->det, tau, h);
    }
}

/* The modes: a good sample keeps NOMINAL or counts towards leaving SAFE, a bad one enters SAFE (and so does
 * a SAFE latched by fault management). */
static void update_mode(aocs_exec_t *exec, int good_sample)
{
    int good = 0;
    if ((good_sample != 0) && (exec->fdir.safe_latched == 0)) {
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
        const aocs_exec_target_t *target = &out->target; /* written by guidance, read by the law */
        aocs_det_output_t est;
        aocs_status_t run_st;             /* the verdict the law runs on */
        uint32_t missing = 0u;
        uint64_t t_start;
        uint32_t c_start;
        int good;
        int sat = 0;

        out->tick = in->tick;
        /* 1. input acceptance */
        in_st = aocs_accept_sample(&exec->accept, exec->law, in, &missing);
        if (in_st == AOCS_OK) {
            /* the actuators' sensors too: a tachometer beyond its physical range is an invalid input
             * (docs/spec.md 5.3.3), not a reading to allocate on */
            in_st = aocs_act_check_sample(&exec->act, in->wheel_speed_radps);
        }
        aocs_exec_count(&exec->counters.missing, missing);
        if ((in_st == AOCS_ERR_INPUT_NOT_FINITE) || (in_st == AOCS_ERR_QUAT_NOT_UNIT) ||
            (in_st == AOCS_ERR_INPUT_INVALID) || (in_st == AOCS_ERR_GYRO_RANGE) ||
            (in_st == AOCS_ERR_WHEEL_SPEED_RANGE)) {
            aocs_exec_count(&exec->counters.invalid, 1u);
        } else if (in_st == AOCS_ERR_INPUT_STALE) {
            aocs_exec_count(&exec->counters.stale, 1u);
        } else {
            /* missing samples were counted above, OK needs nothing */
        }

        t_start = aocs_hal_time_ns();
        c_start = aocs_hal_cycles();
        /* 2. attitude determination (its status is the verdict the law runs on) */
        (void)aocs_det_step(&exec->det, in, in_st, exec->cfg.period_s, &est);
        out->estimate = est;
        /* 3. guidance */
        guide(exec, in, &est, &out->target);
        /* 4. control law */
        att.q_BN = est.q_BN;
        att.w_BN_B = est.w_BN_B;
        att.qd_DN = target->qd_DN;
        att.wd_B = target->wd_B;
        att.wd_dot_B = target->wd_dot_B;
        att.dt_s = exec->cfg.period_s;
        att.u_max_axis = exec->cfg.u_max_axis;
        att.u_max_norm = exec->cfg.u_max_norm;
        orbit.pos_m = in->pos_m;
        orbit.vel_mps = in->vel_mps;
        orbit.dt_s = exec->cfg.period_s;

        /* an attitude law runs on the estimate; an orbit law uses no attitude, only the accepted sample
         * (with the passthrough the two verdicts are the same) */
        run_st = (aocs_law_is_orbit(exec->law) != 0) ? in_st : est.status;
        /* a good sample now completes the recovery (if the law works): enter NOMINAL with a fresh law state */
        if ((run_st == AOCS_OK) && (exec->mode == AOCS_EXEC_MODE_SAFE) &&
            (exec->requested == AOCS_EXEC_MODE_NOMINAL) &&
            (exec->good_run >= (exec->cfg.recover_good_samples - 1u))) {
            law_reset(exec);
        }
        /* the law also runs in SAFE (output unused) so recovery needs a law that works */
        if ((run_st == AOCS_OK) && (exec->law != AOCS_LAW_NONE)) {
            law_st = aocs_exec_law_step(&exec->states, exec->law, &att, &orbit, &u_law);
            if (law_st != AOCS_OK) {
                aocs_exec_count(&exec->counters.law_error, 1u);
            }
        }
        good = 0;
        if ((run_st == AOCS_OK) && (law_st == AOCS_OK)) {
            good = 1;
        }
        update_mode(exec, good);

        if (exec->mode == AOCS_EXEC_MODE_NOMINAL) {
            out->u_unsat = u_law;
            if ((aocs_guidance_has_feedforward(&exec->guidance) != 0) && (aocs_law_is_orbit(exec->law) == 0) &&
                (aocs_law_has_feedforward(exec->law) == 0)) {
                /* SPEC 5.1 feedforward, h_wheels from the tachometers (zero without a wheel array) */
                out->u_ff = aocs_guidance_feedforward(&exec->guidance, target,
                                                      aocs_wheels_h_B(&exec->act.wheels, in->wheel_speed_radps));
                out->u_unsat = aocs_vec3_add(u_law, out->u_ff);
            }
        } else if (exec->mode == AOCS_EXEC_MODE_SAFE) {
            out->u_unsat = aocs_exec_safe_command(&exec->cfg, exec->law, &est);
        } else {
            out->u_unsat = aocs_vec3_zero();
        }
        /* 5. momentum management: the unloading commands; the torque they apply is taken off the wheels'
         * command, so the wheels absorb it and the body sees the law's torque (docs/spec.md 5.9) */
        manage_momentum(exec, in);
        /* 6. actuation */
        aocs_act_step(&exec->act, (exec->mode == AOCS_EXEC_MODE_STANDBY) ? 1 : 0,
                      (exec->momentum.id == AOCS_MOM_NONE) ? out->u_unsat
                                                            : aocs_vec3_sub(out->u_unsat, exec->momentum.out.u_unload_B_Nm),
                      in->wheel_speed_radps, est.w_BN_B, out, &sat);
        /* the torque the body receives until the next sample, for a gyroless estimator's propagation */
        gyroless_torque(exec, in, out);
        /* 7. fault management */
        manage_faults(exec, in, in_st, missing, out);
        out->step_time_ns = aocs_hal_time_ns() - t_start;
        out->step_cycles = aocs_hal_cycles() - c_start;

        out->saturated = sat;
        out->law_status = law_st;
        out->input_status = in_st;
        finish_output(exec, out, step_budget(exec));
        aocs_accept_done(&exec->accept, in_st);
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
        const uint32_t missing_run = aocs_accept_no_sample(&exec->accept);
        aocs_exec_count(&exec->counters.missing, 1u);
        if (exec->mode == AOCS_EXEC_MODE_STANDBY) {
            out->u_unsat = aocs_vec3_zero();
        } else if ((exec->mode == AOCS_EXEC_MODE_NOMINAL) && (missing_run < exec->cfg.missing_max_periods)) {
            /* zero-order hold of the last command over a short gap */
            out->u_unsat = exec->last_u_cmd;
        } else {
            set_mode(exec, AOCS_EXEC_MODE_SAFE);
            out->u_unsat = aocs_vec3_zero(); /* no fresh rate to damp */
        }
        if (exec->momentum.id != AOCS_MOM_NONE) {
            /* no sample: no momentum measured, an unload in progress stops (nothing fires) */
            aocs_mom_input_t mi;
            (void)memset(&mi, 0, sizeof(mi));
            (void)aocs_mom_step(&exec->momentum, &mi);
        }
        aocs_act_step_held(&exec->act, (exec->mode == AOCS_EXEC_MODE_STANDBY) ? 1 : 0, out->u_unsat, out, &sat);
        manage_faults(exec, NULL, AOCS_ERR_INPUT_MISSING, 0u, out);
        out->step_time_ns = aocs_hal_time_ns() - t_start;
        out->step_cycles = aocs_hal_cycles() - c_start;
        out->saturated = sat;
        out->tick = exec->accept.last_tick;
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
        aocs_guidance_set_epoch(&exec->guidance, t0_ns);
    }
    return st;
}

aocs_mom_output_t aocs_exec_momentum(const aocs_exec_t *exec)
{
    return aocs_mom_output((exec != NULL) && (exec->initialised != 0) ? &exec->momentum : NULL);
}

const aocs_evlog_t *aocs_exec_events(const aocs_exec_t *exec)
{
    return ((exec != NULL) && (exec->initialised != 0)) ? &exec->fdir.log : NULL;
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
