/*
 * fsw_node: the SIL flight computer. Translates LCM messages (the wire
 * contract of sil/lcmtypes, docs/wire-contract.md) to and from the firmware
 * executive and does nothing else: no physics, no control logic of its own.
 *
 *   fsw_node CONFIG_FILE
 *
 * Lockstep: every AOCS_SENSORS frame is one tick (decode, check, executive
 * step, publish AOCS_ACTUATOR_CMD). Real time: absolute deadlines at the
 * control rate, stepping with the newest sample or without one. Every wait
 * is bounded; SIGINT/SIGTERM end the run; the final statistics go to stderr
 * (text) and stdout (one JSON line).
 *
 * Host code only (links liblcm); the firmware rules apply to firmware/.
 */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lcm/lcm.h>

#include "aocs/executive.h"
#include "aocs/hal.h"
#include "aocs_lcm_actuator_cmd_t.h"
#include "aocs_lcm_command_t.h"
#include "aocs_lcm_sensors_t.h"
#include "aocs_lcm_status_t.h"
#include "node_checks.h"
#include "node_config.h"
#include "node_hints.h"
#include "node_stats.h"
#include "node_wire.h"

#define CH_SENSORS "AOCS_SENSORS"
#define CH_ACTUATOR "AOCS_ACTUATOR_CMD"
#define CH_COMMAND "AOCS_COMMAND"
#define CH_STATUS "AOCS_STATUS"

#define EXIT_CONFIG 2
#define EXIT_RUNTIME 1
#define LCM_WAIT_MAX_MS 100
#define LCM_ERRORS_MAX 100u
#define NS_PER_MS 1000000ull

typedef struct {
    lcm_t *lcm;
    aocs_node_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;       /* last executive output */
    int have_out;
    aocs_node_seq_t seq;          /* AOCS_SENSORS frame sequence */
    uint64_t frame_cmd;           /* our counters on AOCS_ACTUATOR_CMD / AOCS_STATUS (sent modulo 2^63) */
    uint64_t frame_status;
    uint64_t sensor_frames;       /* AOCS_SENSORS messages received (any content) */
    uint64_t n_foreign;
    uint64_t n_malformed;
    uint64_t n_cmd_accepted;
    uint64_t n_cmd_rejected;
    int64_t last_request;
    int32_t last_request_status;
    aocs_law_id_t nominal_law;    /* law NOMINAL returns to after STANDBY */
    uint64_t t_start_ns;
    uint64_t t_last_sensor_ns;    /* HAL time of the last AOCS_SENSORS message */
    /* real-time mode */
    aocs_node_epoch_t epoch;      /* rotating target: t0 mapped onto the HAL clock */
    aocs_exec_timer_t timer;
    int have_new_sample;
    aocs_lcm_sensors_t latest;
    uint64_t latest_rx_ns;
    int64_t latest_tick;
} node_t;

static volatile sig_atomic_t g_stop = 0;
static node_t g_node;                         /* static: the stats ring is large */
static aocs_node_stats_t g_stats;
static uint64_t g_scratch[AOCS_NODE_STATS_WINDOW];

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

static int64_t to_i64(uint64_t x)
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

static uint64_t overruns(const node_t *n)
{
    return (uint64_t)n->out.counters.overrun + n->timer.slips;
}

static void publish_actuator(node_t *n, aocs_status_t step_rc, int64_t tick, int64_t utime, int deadline_missed)
{
    aocs_lcm_actuator_cmd_t m;
    const aocs_exec_output_t *o = &n->out;
    int i;
    memset(&m, 0, sizeof(m));
    m.protocol_version = AOCS_LCM_ACTUATOR_CMD_T_PROTOCOL_VERSION;
    m.frame = next_frame(&n->frame_cmd);
    m.utime = utime;
    m.tick = tick;
    m.law_id = (int16_t)o->law;
    m.mode = (int8_t)o->mode;
    for (i = 0; i < 3; ++i) {
        m.u_sat[i] = (double)o->u_cmd.v[i];
        m.u_unsat[i] = (double)o->u_unsat.v[i];
    }
    m.saturated = (o->saturated != 0) ? 1 : 0;
    m.step_ns = to_i64(o->step_time_ns);
    m.overrun = ((o->overrun != 0) || (deadline_missed != 0)) ? 1 : 0;
    m.status = step_status(step_rc, o);
    m.n_invalid = (int64_t)o->counters.invalid;
    m.n_stale = (int64_t)o->counters.stale;
    m.n_missing = (int64_t)o->counters.missing;
    m.n_law_error = (int64_t)o->counters.law_error;
    m.n_overrun = to_i64(overruns(n));
    m.n_lost = to_i64(n->seq.lost);
    m.n_duplicate = to_i64(n->seq.duplicate);
    m.n_foreign = to_i64(n->n_foreign);
    m.n_malformed = to_i64(n->n_malformed);
    m.n_cmd_accepted = to_i64(n->n_cmd_accepted);
    m.n_cmd_rejected = to_i64(n->n_cmd_rejected);
    /* the wheel array's allocation of this step (all zero without one) */
    m.n_wheels = (int8_t)n->cfg.exec.wheels.n;
    for (i = 0; i < (int)AOCS_WHEELS_MAX; ++i) {
        m.u_wheels[i] = (double)o->wheels.u_s_nm[i];
    }
    m.wheel_scale = (double)o->wheels.scale;
    m.wheel_limited = (int32_t)(o->wheels.torque_limited_mask | (o->wheels.speed_limited_mask << 8));
    m.wheel_status = (int32_t)o->wheels_status;
    for (i = 0; i < 3; ++i) {
        m.h_total[i] = (double)o->momentum.h_total_B_Nms.v[i];
    }
    m.wheel_speed_margin = (double)o->momentum.speed_margin;
    /* the attitude-determination stage's estimate of this step (telemetry) */
    aocs_node_estimate_to_cmd(&o->estimate, n->exec.cfg.determination.estimator, &m);
    /* the momentum-management stage's commands and dump telemetry of this step */
    {
        const aocs_mom_output_t mom = aocs_exec_momentum(&n->exec);
        aocs_node_momentum_to_cmd(&mom, &n->exec.cfg.momentum, &m);
    }
    if (aocs_lcm_actuator_cmd_t_publish(n->lcm, CH_ACTUATOR, &m) != 0) {
        (void)fprintf(stderr, "fsw_node: publish on %s failed\n", CH_ACTUATOR);
    }
}

static void publish_status(node_t *n, int exiting)
{
    aocs_lcm_status_t m;
    aocs_node_stats_summary_t s = aocs_node_stats_summary(&g_stats, g_scratch);
    memset(&m, 0, sizeof(m));
    m.protocol_version = AOCS_LCM_STATUS_T_PROTOCOL_VERSION;
    m.frame = next_frame(&n->frame_status);
    m.utime = to_i64(aocs_hal_time_ns() / 1000u);
    m.run_mode = (n->cfg.run_mode == AOCS_NODE_RUN_REALTIME) ? AOCS_LCM_STATUS_T_RUN_REALTIME
                                                             : AOCS_LCM_STATUS_T_RUN_LOCKSTEP;
    m.law_id = (int16_t)n->exec.law;
    m.mode = (int8_t)n->exec.mode;
    m.steps = to_i64(g_stats.count);
    m.n_overrun = to_i64(overruns(n));
    m.step_ns_median = to_i64(s.median);
    m.step_ns_p99 = to_i64(s.p99);
    m.step_ns_max = to_i64(s.max);
    m.jitter_ns_max = to_i64(n->timer.jitter_max_abs_ns);
    m.last_request = n->last_request;
    m.last_request_status = n->last_request_status;
    m.n_cmd_accepted = to_i64(n->n_cmd_accepted);
    m.n_cmd_rejected = to_i64(n->n_cmd_rejected);
    m.n_foreign = to_i64(n->n_foreign);
    m.n_malformed = to_i64(n->n_malformed);
    m.exiting = (exiting != 0) ? 1 : 0;
    if (aocs_lcm_status_t_publish(n->lcm, CH_STATUS, &m) != 0) {
        (void)fprintf(stderr, "fsw_node: publish on %s failed\n", CH_STATUS);
    }
}

static void record_step(node_t *n, aocs_status_t rc)
{
    n->have_out = 1;
    if (rc == AOCS_OK) {
        aocs_node_stats_add(&g_stats, n->out.step_time_ns);
    }
}

/* ---- AOCS_SENSORS ------------------------------------------------------- */
static void on_sensors(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    node_t *n = (node_t *)user;
    aocs_lcm_sensors_t msg;
    aocs_node_decode_t d;
    (void)channel;
    n->sensor_frames = aocs_node_add_sat(n->sensor_frames, 1u);
    n->t_last_sensor_ns = aocs_hal_time_ns();
    d = aocs_node_decode_sensors(rbuf->data, rbuf->data_size, &msg);
    if (d == AOCS_NODE_DECODE_MALFORMED) {
        n->n_malformed = aocs_node_add_sat(n->n_malformed, 1u);
        return;
    }
    if (d == AOCS_NODE_DECODE_FOREIGN) {
        n->n_foreign = aocs_node_add_sat(n->n_foreign, 1u);
        return;
    }
    if (aocs_node_seq_accepted(aocs_node_seq_check(&n->seq, msg.frame)) != 0) {
        if (n->cfg.run_mode == AOCS_NODE_RUN_LOCKSTEP) {
            aocs_exec_input_t in;
            aocs_status_t rc;
            aocs_node_lockstep_input(&msg, &in);
            rc = aocs_exec_step(&n->exec, &in, &n->out);
            record_step(n, rc);
            publish_actuator(n, rc, msg.tick, msg.utime, 0);
        } else {
            /* real time: keep the newest sample for the next deadline */
            n->latest = msg;
            n->latest_rx_ns = n->t_last_sensor_ns;
            n->latest_tick = msg.tick;
            n->have_new_sample = 1;
        }
    }
    (void)aocs_lcm_sensors_t_decode_cleanup(&msg);
}

/* ---- AOCS_COMMAND ------------------------------------------------------- */
static void on_command(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    node_t *n = (node_t *)user;
    aocs_lcm_command_t msg;
    aocs_status_t st;
    aocs_node_decode_t d;
    (void)channel;
    d = aocs_node_decode_command(rbuf->data, rbuf->data_size, &msg);
    if (d == AOCS_NODE_DECODE_MALFORMED) {
        n->n_malformed = aocs_node_add_sat(n->n_malformed, 1u);
        return;
    }
    if (d == AOCS_NODE_DECODE_FOREIGN) {
        n->n_foreign = aocs_node_add_sat(n->n_foreign, 1u);
        return;
    }
    st = aocs_node_command_apply(&n->exec, &n->nominal_law, &msg);
    n->last_request = msg.request;
    n->last_request_status = (int32_t)st;
    if (st == AOCS_OK) {
        n->n_cmd_accepted = aocs_node_add_sat(n->n_cmd_accepted, 1u);
    } else {
        n->n_cmd_rejected = aocs_node_add_sat(n->n_cmd_rejected, 1u);
        (void)fprintf(stderr, "fsw_node: command %lld rejected: %s\n", (long long)msg.request,
                      aocs_status_name(st));
    }
    (void)aocs_lcm_command_t_decode_cleanup(&msg);
    publish_status(n, 0); /* acknowledgement */
}

/* ---- configuration ------------------------------------------------------ */
static int load_config(node_t *n, const char *path)
{
    char err[AOCS_NODE_ERR_MAX];
    char hint[AOCS_NODE_ERR_MAX];
    aocs_status_t st;
    if (aocs_node_config_load(path, &n->cfg, err, sizeof(err)) != 0) {
        (void)fprintf(stderr, "fsw_node: config error: %s\n", err);
        return 1;
    }
    if (aocs_node_timeouts_check(&n->cfg, err, sizeof(err)) != 0) {
        (void)fprintf(stderr, "fsw_node: config error: %s: %s\n", path, err);
        return 1;
    }
    n->cfg.exec.clock = (n->cfg.run_mode == AOCS_NODE_RUN_REALTIME) ? AOCS_EXEC_CLOCK_REALTIME
                                                                    : AOCS_EXEC_CLOCK_LOCKSTEP;
    st = aocs_exec_init(&n->exec, &n->cfg.exec);
    if (st != AOCS_OK) {
        (void)fprintf(stderr, "fsw_node: config error: %s: the executive rejected the configuration of law '%s': %s (check %s)\n",
                      path, aocs_law_name(n->cfg.exec.law), aocs_status_name(st),
                      aocs_node_config_status_hint(st, n->cfg.exec.law, hint, sizeof(hint)));
        return 1;
    }
    n->nominal_law = n->cfg.exec.law;
    return 0;
}

/* ---- loops -------------------------------------------------------------- */
static int lcm_wait(node_t *n, uint64_t wait_ns, unsigned *errors)
{
    /* whole ms, at least 1, at most LCM_WAIT_MAX_MS: clamped in uint64_t before the int conversion */
    const uint64_t wait_ms = (wait_ns / NS_PER_MS) + (((wait_ns % NS_PER_MS) != 0u) ? 1u : 0u);
    int ms = (wait_ms > (uint64_t)LCM_WAIT_MAX_MS) ? LCM_WAIT_MAX_MS : (int)wait_ms;
    int rc;
    if (ms < 1) {
        ms = 1;
    }
    rc = lcm_handle_timeout(n->lcm, ms);
    if ((rc < 0) && (g_stop == 0)) {
        (*errors)++;
        if (*errors > LCM_ERRORS_MAX) {
            (void)fprintf(stderr, "fsw_node: lcm_handle_timeout keeps failing: %s\n", strerror(errno));
            return 1;
        }
    } else {
        *errors = 0u;
    }
    return 0;
}

static uint64_t seconds_ns(double s)
{
    return aocs_node_seconds_to_ns(s);
}

static const char *run_lockstep(node_t *n, int *failed)
{
    uint64_t idle_ns = seconds_ns(n->cfg.idle_timeout_s);
    uint64_t run_ns = seconds_ns(n->cfg.run_timeout_s);
    uint64_t status_ns = seconds_ns(n->cfg.status_period_s);
    uint64_t next_status = n->t_start_ns; /* the first heartbeat at once: the plant starts on it */
    unsigned errors = 0u;
    n->t_last_sensor_ns = n->t_start_ns;
    while (g_stop == 0) {
        uint64_t now = aocs_hal_time_ns();
        uint64_t wait = idle_ns;
        uint64_t idle_end = n->t_last_sensor_ns + idle_ns;
        if ((run_ns > 0u) && (now >= n->t_start_ns + run_ns)) {
            return "run_timeout";
        }
        if (now >= idle_end) {
            return "idle";
        }
        if (now >= next_status) {
            publish_status(n, 0);
            next_status = now + status_ns;
        }
        if (idle_end - now < wait) {
            wait = idle_end - now;
        }
        if (lcm_wait(n, wait, &errors) != 0) {
            *failed = 1;
            return "lcm_error";
        }
    }
    return "signal";
}

static const char *run_realtime(node_t *n, int *failed)
{
    uint64_t run_ns = seconds_ns(n->cfg.run_timeout_s);
    uint64_t status_ns = seconds_ns(n->cfg.status_period_s);
    uint64_t next_status = n->t_start_ns; /* the first heartbeat at once: the plant starts on it */
    uint64_t deadline = n->t_start_ns + n->exec.period_ns;
    unsigned errors = 0u;
    if (aocs_exec_timer_init(&n->timer, n->exec.period_ns, deadline) != AOCS_OK) {
        *failed = 1;
        return "timer_error";
    }
    while (g_stop == 0) {
        uint64_t now = aocs_hal_time_ns();
        uint64_t slips_before;
        aocs_status_t rc;
        int missed;
        if ((run_ns > 0u) && (now >= n->t_start_ns + run_ns)) {
            return "run_timeout";
        }
        /* receive until 1 ms before the deadline, then sleep to it exactly */
        if (now + NS_PER_MS < deadline) {
            if (lcm_wait(n, deadline - now - NS_PER_MS, &errors) != 0) {
                *failed = 1;
                return "lcm_error";
            }
            continue;
        }
        aocs_hal_sleep_until_ns(deadline);
        slips_before = n->timer.slips;
        (void)aocs_exec_timer_period_start(&n->timer, aocs_hal_time_ns(), &deadline);
        missed = (n->timer.slips != slips_before) ? 1 : 0;
        if (n->have_new_sample != 0) {
            aocs_exec_input_t in;
            /* the sensor time base is the HAL clock here: sim time 0 of the plant (the
             * rotating target's t0) is rx time - t_s, set by the first sample and moved
             * only by K consistent later ones (node_wire.h, aocs_node_epoch_update) */
            if (aocs_node_epoch_update(&n->epoch, n->latest_rx_ns, aocs_node_seconds_to_ns(n->latest.t_s),
                                       n->cfg.exec.stale_timeout_ns) != 0) {
                (void)aocs_exec_set_target_epoch(&n->exec, n->epoch.t0_ns);
            }
            aocs_node_sensors_to_input(&n->latest, n->latest_rx_ns, &in);
            n->have_new_sample = 0;
            rc = aocs_exec_step(&n->exec, &in, &n->out);
            record_step(n, rc);
            publish_actuator(n, rc, n->latest_tick, to_i64(aocs_hal_time_ns() / 1000u), missed);
        } else {
            rc = aocs_exec_step_no_input(&n->exec, &n->out);
            record_step(n, rc);
            publish_actuator(n, rc, n->latest_tick, to_i64(aocs_hal_time_ns() / 1000u), missed);
        }
        now = aocs_hal_time_ns();
        if (now >= next_status) {
            publish_status(n, 0);
            next_status = now + status_ns;
        }
    }
    return "signal";
}

/* ---- final report ------------------------------------------------------- */
/*
 * The guidance part of the exit summary: mode, and in slew mode the last slew's start and profile end
 * (sensor time, s; lockstep: sim time) as the firmware planned them, so the tools report the
 * flight software's own profile (null before any slew started).
 */
static void guidance_summary(const node_t *n, char *buf, size_t size)
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

static void report(node_t *n, const char *reason)
{
    aocs_node_stats_summary_t s = aocs_node_stats_summary(&g_stats, g_scratch);
    aocs_exec_counters_t c = aocs_exec_counters(&n->exec);
    double jitter_rms = (double)aocs_exec_timer_jitter_rms_ns(&n->timer);
    const char *run = (n->cfg.run_mode == AOCS_NODE_RUN_REALTIME) ? "realtime" : "lockstep";
    char guidance[320];
    guidance_summary(n, guidance, sizeof(guidance));
    (void)fprintf(stderr,
                  "fsw_node: %s end (%s): steps=%llu overruns=%llu step_ns median=%llu p99=%llu max=%llu "
                  "jitter_ns max=%llu rms=%.0f lost=%llu dup=%llu jump=%llu seq_resync=%llu exec_resync=%lu "
                  "foreign=%llu malformed=%llu\n",
                  run, reason, (unsigned long long)g_stats.count, (unsigned long long)overruns(n),
                  (unsigned long long)s.median, (unsigned long long)s.p99, (unsigned long long)s.max,
                  (unsigned long long)n->timer.jitter_max_abs_ns, jitter_rms, (unsigned long long)n->seq.lost,
                  (unsigned long long)n->seq.duplicate, (unsigned long long)n->seq.jump,
                  (unsigned long long)n->seq.resyncs, (unsigned long)n->exec.accept.resyncs,
                  (unsigned long long)n->n_foreign, (unsigned long long)n->n_malformed);
    (void)printf("{\"fsw_node\": {\"reason\": \"%s\", \"run_mode\": \"%s\", \"law\": \"%s\", \"mode\": \"%s\", "
                 "\"steps\": %llu, \"overruns\": %llu, \"slips\": %llu, "
                 "\"step_ns\": {\"n\": %llu, \"median\": %llu, \"p99\": %llu, \"max\": %llu}, "
                 "\"jitter_ns\": {\"max_abs\": %llu, \"rms\": %.1f}, "
                 "\"sensor_frames\": %llu, \"lost\": %llu, \"duplicate\": %llu, \"foreign\": %llu, \"malformed\": %llu, "
                 "\"invalid\": %lu, \"stale\": %lu, \"missing\": %lu, \"law_error\": %lu, "
                 "\"mode_transitions\": %lu, \"saturated\": %lu, "
                 "\"cmd_accepted\": %llu, \"cmd_rejected\": %llu, \"guidance\": %s}}\n",
                 reason, run, aocs_law_name(n->exec.law), aocs_exec_mode_name(n->exec.mode),
                 (unsigned long long)g_stats.count, (unsigned long long)overruns(n),
                 (unsigned long long)n->timer.slips, (unsigned long long)s.n, (unsigned long long)s.median,
                 (unsigned long long)s.p99, (unsigned long long)s.max,
                 (unsigned long long)n->timer.jitter_max_abs_ns, jitter_rms,
                 (unsigned long long)n->sensor_frames, (unsigned long long)n->seq.lost,
                 (unsigned long long)n->seq.duplicate, (unsigned long long)n->n_foreign,
                 (unsigned long long)n->n_malformed, (unsigned long)c.invalid, (unsigned long)c.stale,
                 (unsigned long)c.missing, (unsigned long)c.law_error, (unsigned long)c.mode_transitions,
                 (unsigned long)c.saturated, (unsigned long long)n->n_cmd_accepted,
                 (unsigned long long)n->n_cmd_rejected, guidance);
    (void)fflush(stdout);
}

static void usage(void)
{
    (void)fprintf(stderr, "usage: fsw_node CONFIG_FILE\n"
                          "  SIL flight computer: LCM (AOCS_SENSORS, AOCS_COMMAND) -> executive ->\n"
                          "  LCM (AOCS_ACTUATOR_CMD, AOCS_STATUS). Config format: docs/wire-contract.md\n");
}

int main(int argc, char **argv)
{
    node_t *n = &g_node;
    struct sigaction sa;
    const char *reason;
    int failed = 0;

    if ((argc != 2) || (strcmp(argv[1], "-h") == 0) || (strcmp(argv[1], "--help") == 0)) {
        usage();
        return (argc == 2) ? 0 : EXIT_CONFIG;
    }
    memset(n, 0, sizeof(*n));
    aocs_node_stats_reset(&g_stats);
    aocs_node_seq_reset(&n->seq);
    n->last_request = -1;
    n->latest_tick = -1;
    if (load_config(n, argv[1]) != 0) {
        return EXIT_CONFIG;
    }

    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = on_signal;
    (void)sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0; /* no SA_RESTART: a signal ends the current bounded wait early */
    (void)sigaction(SIGINT, &sa, NULL);
    (void)sigaction(SIGTERM, &sa, NULL);

    n->lcm = lcm_create((n->cfg.lcm_url[0] != '\0') ? n->cfg.lcm_url : NULL);
    if (n->lcm == NULL) {
        (void)fprintf(stderr, "fsw_node: lcm_create(%s) failed\n",
                      (n->cfg.lcm_url[0] != '\0') ? n->cfg.lcm_url : "default");
        return EXIT_RUNTIME;
    }
    if ((lcm_subscribe(n->lcm, CH_SENSORS, on_sensors, n) == NULL) ||
        (lcm_subscribe(n->lcm, CH_COMMAND, on_command, n) == NULL)) {
        (void)fprintf(stderr, "fsw_node: lcm_subscribe failed\n");
        lcm_destroy(n->lcm);
        return EXIT_RUNTIME;
    }
    (void)fprintf(stderr, "fsw_node: %s, law %s, period %.6f s, ready\n",
                  (n->cfg.run_mode == AOCS_NODE_RUN_REALTIME) ? "realtime" : "lockstep",
                  aocs_law_name(n->exec.law), (double)n->exec.period_ns * 1.0e-9);
    n->t_start_ns = aocs_hal_time_ns();
    if (n->cfg.run_mode == AOCS_NODE_RUN_REALTIME) {
        reason = run_realtime(n, &failed);
    } else {
        reason = run_lockstep(n, &failed);
    }
    publish_status(n, 1);
    report(n, reason);
    lcm_destroy(n->lcm);
    return (failed != 0) ? EXIT_RUNTIME : 0;
}
