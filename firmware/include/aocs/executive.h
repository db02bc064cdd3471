/*
 * Fixed-rate executive: owns one control period (ARCHITECTURE.md "data
 * path"): check the inputs, pick the mode, run the selected law, saturate,
 * time the step against its budget, report counters.
 *
 *   aocs_exec_config_default(&cfg);        fill defaults, then set the law,
 *   cfg.law = AOCS_LAW_QUAT_PD;            its config, limits, period
 *   cfg.laws.quat_pd = ...;
 *   aocs_exec_init(&exec, &cfg);           validates everything
 *   loop: aocs_exec_step(&exec, &in, &out) (lockstep: one call per sensor sample)
 *   aocs_exec_select(&exec, law, &target)  run-time command (SIL command message)
 *
 * Real-time mode adds the period timer (absolute deadlines, no drift):
 *   aocs_exec_timer_init(&tmr, period_ns, first_deadline_ns);
 *   loop: aocs_hal_sleep_until_ns(deadline);
 *         aocs_exec_timer_period_start(&tmr, aocs_hal_time_ns(), &deadline);
 *         aocs_exec_step(...) or aocs_exec_step_no_input(...) when no sample came.
 *
 * Modes: STANDBY (zero command), NOMINAL (selected law), SAFE (attitude:
 * u = -k_safe w within the limits; orbit: zero force). The executive enters
 * SAFE on an invalid, stale or missing input or a law error, and returns to
 * the requested mode after recover_good_samples consecutive good samples
 * (a good sample: valid, fresh, no gap, and the law evaluates without error;
 * in SAFE the law is evaluated in the shadow to know that).
 *
 * The saturated command never exceeds the limits, whatever happens: NaN or
 * Inf from anywhere gives a zero command.
 *
 * Guidance (guidance.c): a target frame D that rotates at the constant rate
 * target_rotation_rate_D (rad/s, in D) relative to N. At each step, from the
 * sensor time t (exact closed form, no accumulated drift):
 *     qd(t) = dq(w (t - t0)) (x) qd0,  dq(theta) = [sin(|theta|/2) theta/|theta|; cos(|theta|/2)]
 * (the solution of qd' = 0.5 Xi(qd) w, the plant's Plant.target(t)), and
 *     wd_B = A(qe) w,            qe = q (x) qd^-1  (D's rate in B: we = w - wd_B)
 *     wd_dot_B = wd_B x w_BN_B   (d/dt of the B components, see guidance.c)
 * qd0 is the configured target, t0 = target_t0_ns (lockstep: sim time 0);
 * a new target from aocs_exec_select becomes qd0 at the time of the last
 * sample. A zero rate leaves the target exactly as given (bit for bit).
 *
 * Reaction wheels (wheels.c, wheel_array.h): with cfg.wheels.n != 0 the
 * saturated body torque is allocated to the wheels every step (minimum norm,
 * one uniform scale, speed protection from the tachometer speeds of the
 * sample); u_cmd is then the body torque the wheels deliver (the same
 * direction) and out.wheels holds the wheel torque commands, out.momentum the
 * total momentum and the speed margin. The motor commands include the
 * friction feedforward and the null-space wheel speed management of the
 * array's configuration (docs/spec.md 5.3.2) in NOMINAL and SAFE; STANDBY
 * commands no motor torque at all. Non-finite tachometer speeds give a
 * zero wheel command (wheels_status says why). Without an array nothing
 * changes.
 *
 * Gain tables (gain_tables.c): the designs compiled into gains/aocs_gains.h
 * by name or id, so a config can say "<design name>" instead of 18 numbers;
 * `aocs gains` registers them in gains/gain_tables.def.
 *
 * The laws themselves, their configs, states, budgets and config fields are
 * rows of aocs/laws.def (the law registry); everything here that lists laws
 * is expanded from it.
 */
#ifndef AOCS_EXECUTIVE_H
#define AOCS_EXECUTIVE_H

/*
 * The umbrella of the executive's public headers, one per concern
 * (aocs/exec/), and of the pipeline's stages; every #include "aocs/executive.h"
 * keeps working.
 */
#include "aocs/exec/law_dispatch.h"  /* law ids, configs, states, dispatch (laws.def) */
#include "aocs/exec/gain_tables.h"   /* compiled gain tables */
#include "aocs/exec/modes.h"         /* STANDBY / NOMINAL / SAFE, clock */
#include "aocs/exec/io.h"            /* input sample, output, counters, target */
#include "aocs/exec/timing.h"        /* period timer, period conversion, budgets */
#include "aocs/exec/config.h"        /* aocs_exec_config_t, defaults, accepted ranges */
#include "aocs/exec/acceptance.h"    /* input acceptance stage */
#include "aocs/estimation/determination.h"
#include "aocs/guidance/guidance.h"
#include "aocs/actuation/actuation.h"
#include "aocs/momentum/momentum.h"
#include "aocs/exec/pipeline.h"      /* aocs_exec_t: init, select, step */

#endif /* AOCS_EXECUTIVE_H */
