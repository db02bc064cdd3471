/*
 * The fixed-rate executive and its flight pipeline (ARCHITECTURE.md "The
 * flight pipeline"; docs/architecture.md): one control period is
 *
 *   accept input -> determine attitude -> guide -> control law -> actuate -> manage momentum
 *
 * each stage a small registry of implementations selected by configuration
 * (one .def of rows each, like the laws' laws.def), in its own folder:
 *
 *   stage                 header (public)                      rows                          source
 *   input acceptance      aocs/exec/acceptance.h               exec/acceptance.def (clock)   src/acceptance/
 *   attitude determin.    aocs/estimation/determination.h      estimation/determination.def  src/estimation/
 *   guidance              aocs/guidance/guidance.h             guidance/guidance_modes.def   src/guidance/
 *   control law           aocs/exec/law_dispatch.h             laws.def                      src/control/
 *   actuation             aocs/actuation/actuation.h           actuation/actuation.def       src/actuation/
 *   momentum management   aocs/momentum/momentum.h             momentum/momentum.def         src/momentum/
 *
 * The executive (aocs/exec/pipeline.h, src/executive/) only sequences them,
 * owns the modes (STANDBY / NOMINAL / SAFE, aocs/exec/modes.h) and times the
 * step (aocs/exec/timing.h). Its configuration is aocs/exec/config.h (rows of
 * config_fields.def and laws.def), its input, output and counters
 * aocs/exec/io.h, the compiled gain tables aocs/exec/gain_tables.h.
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
 * This header is the umbrella: it includes every header above, so one
 * #include "aocs/executive.h" gives the whole executive.
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
