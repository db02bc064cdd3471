/* The node logic shared by fsw_node and the in-process node (node_core.h). */
#include "node_core.h"

#include <stdio.h>
#include <string.h>

#include "aocs/hal.h"
#include "node_checks.h"
#include "node_hints.h"

int64_t aocs_node_to_i64(uint64_t x)
{
    return (x > (uint64_t)INT64_MAX) ? INT64_MAX : (int64_t)x;
}

/* next value of one of our frame counters: 0, 1, ... INT64_MAX, then 0 again (no signed arithmetic) */
static int64_t next_frame(uint64_t *counter)
{
    const int64_t f = (int64_t)(*counter & (uint64_t)INT64_MAX);
    *counter += 1u; /* unsigned: wraps modulo 2^64, and the mask above keeps the sent value in range */
    return f;
}

/* status reported with a command: the first thing that went wrong */
static int32_t step_status(aocs_status_t step_rc, const aocs_exec_output_t *out)
{
    aocs_status_t st = step_rc;
    if (st == AOCS_OK) {
        st = out->input_status;
    }
    if (st == AOCS_OK) {
        st = out->law_status;
    }
    if (st == AOCS_OK) {
        st = out->wheels_status; /* an allocation refused or replaced by the output guard (docs/spec.md 5.3.3) */
    }
    return (int32_t)st;
}

void aocs_node_core_reset(aocs_node_core_t *n)
{
    memset(n, 0, sizeof(*n));
    aocs_node_stats_reset(&n->stats);
    aocs_node_seq_reset(&n->seq);
    n->last_request = -1;
}

int aocs_node_core_configure(aocs_node_core_t *n, const char *name, char *err, size_t err_size)
{
    char msg[AOCS_NODE_ERR_MAX];
    char hint[AOCS_NODE_ERR_MAX];
    aocs_status_t st;
    if (aocs_node_timeouts_check(&n->cfg, msg, sizeof(msg)) != 0) {
        (void)snprintf(err, err_size, "%s: %s", name, msg);
        return 1;
    }
    n->cfg.exec.clock = (n->cfg.run_mode == AOCS_NODE_RUN_REALTIME) ? AOCS_EXEC_CLOCK_REALTIME
                                                                    : AOCS_EXEC_CLOCK_LOCKSTEP;
    st = aocs_exec_init(&n->exec, &n->cfg.exec);
    if (st != AOCS_OK) {
        (void)snprintf(err, err_size, "%s: the executive rejected the configuration of law '%s': %s (check %s)",
                       name, aocs_law_name(n->cfg.exec.law), aocs_status_name(st),
                       aocs_node_config_status_hint(st, n->cfg.exec.law, hint, sizeof(hint)));
        return 1;
    }
    n->nominal_law = n->cfg.exec.law;
    return 0;
}

aocs_node_rx_t aocs_node_core_receive(aocs_node_core_t *n, const void *data, uint32_t size,
                                      aocs_lcm_sensors_t *msg)
{
    aocs_node_decode_t d;
    n->sensor_frames = aocs_node_add_sat(n->sensor_frames, 1u);
    d = aocs_node_decode_sensors(data, size, msg);
    if (d == AOCS_NODE_DECODE_MALFORMED) {
        n->n_malformed = aocs_node_add_sat(n->n_malformed, 1u);
        return AOCS_NODE_RX_MALFORMED;
    }
    if (d == AOCS_NODE_DECODE_FOREIGN) {
        n->n_foreign = aocs_node_add_sat(n->n_foreign, 1u);
        return AOCS_NODE_RX_FOREIGN;
    }
    if (aocs_node_seq_accepted(aocs_node_seq_check(&n->seq, msg->frame)) == 0) {
        (void)aocs_lcm_sensors_t_decode_cleanup(msg);
        return AOCS_NODE_RX_DROPPED;
    }
    return AOCS_NODE_RX_ACCEPTED;
}

void aocs_node_core_record(aocs_node_core_t *n, aocs_status_t rc)
{
    n->have_out = 1;
    if (rc == AOCS_OK) {
        aocs_node_stats_add(&n->stats, n->out.step_time_ns);
    }
}

int aocs_node_core_lockstep(aocs_node_core_t *n, const void *data, uint32_t size, aocs_lcm_actuator_cmd_t *reply)
{
    aocs_lcm_sensors_t msg;
    aocs_exec_input_t in;
    aocs_status_t rc;
    if (aocs_node_core_receive(n, data, size, &msg) != AOCS_NODE_RX_ACCEPTED) {
        return 0;
    }
    aocs_node_lockstep_input(&msg, &in);
    rc = aocs_exec_step(&n->exec, &in, &n->out);
    aocs_node_core_record(n, rc);
    aocs_node_core_actuator(n, rc, msg.tick, msg.utime, 0, reply);
    (void)aocs_lcm_sensors_t_decode_cleanup(&msg);
    return 1;
}

uint64_t aocs_node_core_overruns(const aocs_node_core_t *n)
{
    return (uint64_t)n->out.counters.overrun + n->timer.slips;
}

void aocs_node_core_actuator(aocs_node_core_t *n, aocs_status_t step_rc, int64_t tick, int64_t utime,
                             int deadline_missed, aocs_lcm_actuator_cmd_t *m)
{
    const aocs_exec_output_t *o = &n->out;
    int i;
    memset(m, 0, sizeof(*m));
    m->protocol_version = AOCS_LCM_ACTUATOR_CMD_T_PROTOCOL_VERSION;
    m->frame = next_frame(&n->frame_cmd);
    m->utime = utime;
    m->tick = tick;
    m->law_id = (int16_t)o->law;
    m->mode = (int8_t)o->mode;
    for (i = 0; i < 3; ++i) {
        m->u_sat[i] = (double)o->u_cmd.v[i];
        m->u_unsat[i] = (double)o->u_unsat.v[i];
    }
    m->saturated = (o->saturated != 0) ? 1 : 0;
    m->step_ns = aocs_node_to_i64(o->step_time_ns);
    m->overrun = ((o->overrun != 0) || (deadline_missed != 0)) ? 1 : 0;
    m->status = step_status(step_rc, o);
    m->n_invalid = (int64_t)o->counters.invalid;
    m->n_stale = (int64_t)o->counters.stale;
    m->n_missing = (int64_t)o->counters.missing;
    m->n_law_error = (int64_t)o->counters.law_error;
    m->n_overrun = aocs_node_to_i64(aocs_node_core_overruns(n));
    m->n_lost = aocs_node_to_i64(n->seq.lost);
    m->n_duplicate = aocs_node_to_i64(n->seq.duplicate);
    m->n_foreign = aocs_node_to_i64(n->n_foreign);
    m->n_malformed = aocs_node_to_i64(n->n_malformed);
    m->n_cmd_accepted = aocs_node_to_i64(n->n_cmd_accepted);
    m->n_cmd_rejected = aocs_node_to_i64(n->n_cmd_rejected);
    /* the wheel array's allocation of this step (all zero without one) */
    m->n_wheels = (int8_t)n->cfg.exec.wheels.n;
    for (i = 0; i < (int)AOCS_WHEELS_MAX; ++i) {
        m->u_wheels[i] = (double)o->wheels.u_s_nm[i];
    }
    m->wheel_scale = (double)o->wheels.scale;
    m->wheel_limited = (int32_t)(o->wheels.torque_limited_mask | (o->wheels.speed_limited_mask << 8));
    m->wheel_status = (int32_t)o->wheels_status;
    for (i = 0; i < 3; ++i) {
        m->h_total[i] = (double)o->momentum.h_total_B_Nms.v[i];
    }
    m->wheel_speed_margin = (double)o->momentum.speed_margin;
    /* the attitude-determination stage's estimate of this step (telemetry) */
    aocs_node_estimate_to_cmd(&o->estimate, n->exec.cfg.determination.estimator, m);
    /* the momentum-management stage's commands and dump telemetry of this step */
    {
        const aocs_mom_output_t mom = aocs_exec_momentum(&n->exec);
        aocs_node_momentum_to_cmd(&mom, &n->exec.cfg.momentum, m);
    }
}

int aocs_node_core_command(aocs_node_core_t *n, const void *data, uint32_t size)
{
    aocs_lcm_command_t msg;
    aocs_status_t st;
    const aocs_node_decode_t d = aocs_node_decode_command(data, size, &msg);
    if (d == AOCS_NODE_DECODE_MALFORMED) {
        n->n_malformed = aocs_node_add_sat(n->n_malformed, 1u);
        return 0;
    }
    if (d == AOCS_NODE_DECODE_FOREIGN) {
        n->n_foreign = aocs_node_add_sat(n->n_foreign, 1u);
        return 0;
    }
    st = aocs_node_command_apply(&n->exec, &n->nominal_law, &msg);
    n->last_request = msg.request;
    n->last_request_status = (int32_t)st;
    if (st == AOCS_OK) {
        n->n_cmd_accepted = aocs_node_add_sat(n->n_cmd_accepted, 1u);
    } else {
        n->n_cmd_rejected = aocs_node_add_sat(n->n_cmd_rejected, 1u);
    }
    (void)aocs_lcm_command_t_decode_cleanup(&msg);
    return 1;
}

void aocs_node_core_status(aocs_node_core_t *n, int exiting, int64_t utime_us, aocs_lcm_status_t *m)
{
    aocs_node_stats_summary_t s = aocs_node_stats_summary(&n->stats, n->scratch);
    memset(m, 0, sizeof(*m));
    m->protocol_version = AOCS_LCM_STATUS_T_PROTOCOL_VERSION;
    m->frame = next_frame(&n->frame_status);
    m->utime = utime_us;
    m->run_mode = (n->cfg.run_mode == AOCS_NODE_RUN_REALTIME) ? AOCS_LCM_STATUS_T_RUN_REALTIME
                                                              : AOCS_LCM_STATUS_T_RUN_LOCKSTEP;
    m->law_id = (int16_t)n->exec.law;
    m->mode = (int8_t)n->exec.mode;
    m->steps = aocs_node_to_i64(n->stats.count);
    m->n_overrun = aocs_node_to_i64(aocs_node_core_overruns(n));
    m->step_ns_median = aocs_node_to_i64(s.median);
    m->step_ns_p99 = aocs_node_to_i64(s.p99);
    m->step_ns_max = aocs_node_to_i64(s.max);
    m->jitter_ns_max = aocs_node_to_i64(n->timer.jitter_max_abs_ns);
    m->last_request = n->last_request;
    m->last_request_status = n->last_request_status;
    m->n_cmd_accepted = aocs_node_to_i64(n->n_cmd_accepted);
    m->n_cmd_rejected = aocs_node_to_i64(n->n_cmd_rejected);
    m->n_foreign = aocs_node_to_i64(n->n_foreign);
    m->n_malformed = aocs_node_to_i64(n->n_malformed);
    {
        const aocs_evlog_t *log = aocs_exec_events(&n->exec);
        m->n_events = (int64_t)aocs_evlog_count(log);
        m->n_events_critical = (int64_t)aocs_evlog_count_at_least(log, AOCS_SEV_CRITICAL);
    }
    m->exiting = (exiting != 0) ? 1 : 0;
}

int aocs_node_core_event(aocs_node_core_t *n, aocs_lcm_event_t *m)
{
    aocs_event_t e;
    uint32_t lost = 0u;
    int got = 0;
    if (aocs_evlog_next(aocs_exec_events(&n->exec), n->event_seq_sent, &e, &lost) == AOCS_OK) {
        aocs_node_event_to_msg(&e, lost, m);
        m->frame = next_frame(&n->frame_event);
        m->utime = aocs_node_to_i64(aocs_hal_time_ns() / 1000u);
        n->event_seq_sent = e.seq;
        got = 1;
    }
    return got;
}

/*
 * The guidance part of the exit summary: mode, and in slew mode the last slew's start and profile end
 * (sensor time, s; lockstep: sim time) as the firmware planned them, so the tools report the
 * flight software's own profile (null before any slew started).
 */
static void guidance_summary(const aocs_node_core_t *n, char *buf, size_t size)
{
    const aocs_exec_t *e = &n->exec;
    if (e->cfg.guidance.mode != AOCS_GUIDANCE_MODE_SLEW) {
        (void)snprintf(buf, size, "{\"mode\": \"step\"}");
    } else if (e->guidance.slew_pending != 0) {
        (void)snprintf(buf, size, "{\"mode\": \"slew\", \"slew_start_s\": null, \"profile_end_s\": null}");
    } else {
        const double t0 = (double)e->guidance.slew_t0_ns * 1e-9;
        (void)snprintf(buf, size,
                       "{\"mode\": \"slew\", \"slew_start_s\": %.9g, \"profile_end_s\": %.9g, "
                       "\"angle_rad\": %.9g, \"peak_rate_radps\": %.9g, \"peak_accel_radps2\": %.9g}",
                       t0, t0 + (double)e->guidance.slew.t_end_s, (double)e->guidance.slew.theta_f_rad, (double)e->guidance.slew.rate_radps,
                       (double)e->guidance.slew.accel_radps2);
    }
}

int aocs_node_core_report_json(aocs_node_core_t *n, const char *reason, char *buf, size_t size)
{
    aocs_node_stats_summary_t s = aocs_node_stats_summary(&n->stats, n->scratch);
    aocs_exec_counters_t c = aocs_exec_counters(&n->exec);
    double jitter_rms = (double)aocs_exec_timer_jitter_rms_ns(&n->timer);
    const char *run = (n->cfg.run_mode == AOCS_NODE_RUN_REALTIME) ? "realtime" : "lockstep";
    char guidance[320];
    guidance_summary(n, guidance, sizeof(guidance));
    return snprintf(buf, size,
                    "{\"fsw_node\": {\"reason\": \"%s\", \"run_mode\": \"%s\", \"law\": \"%s\", \"mode\": \"%s\", "
                    "\"steps\": %llu, \"overruns\": %llu, \"slips\": %llu, "
                    "\"step_ns\": {\"n\": %llu, \"median\": %llu, \"p99\": %llu, \"max\": %llu}, "
                    "\"jitter_ns\": {\"max_abs\": %llu, \"rms\": %.1f}, "
                    "\"sensor_frames\": %llu, \"lost\": %llu, \"duplicate\": %llu, \"foreign\": %llu, \"malformed\": %llu, "
                    "\"invalid\": %lu, \"stale\": %lu, \"missing\": %lu, \"law_error\": %lu, "
                    "\"mode_transitions\": %lu, \"saturated\": %lu, "
                    "\"cmd_accepted\": %llu, \"cmd_rejected\": %llu, \"guidance\": %s}}",
                    reason, run, aocs_law_name(n->exec.law), aocs_exec_mode_name(n->exec.mode),
                    (unsigned long long)n->stats.count, (unsigned long long)aocs_node_core_overruns(n),
                    (unsigned long long)n->timer.slips, (unsigned long long)s.n, (unsigned long long)s.median,
                    (unsigned long long)s.p99, (unsigned long long)s.max,
                    (unsigned long long)n->timer.jitter_max_abs_ns, jitter_rms,
                    (unsigned long long)n->sensor_frames, (unsigned long long)n->seq.lost,
                    (unsigned long long)n->seq.duplicate, (unsigned long long)n->n_foreign,
                    (unsigned long long)n->n_malformed, (unsigned long)c.invalid, (unsigned long)c.stale,
                    (unsigned long)c.missing, (unsigned long)c.law_error, (unsigned long)c.mode_transitions,
                    (unsigned long)c.saturated, (unsigned long long)n->n_cmd_accepted,
                    (unsigned long long)n->n_cmd_rejected, guidance);
}
