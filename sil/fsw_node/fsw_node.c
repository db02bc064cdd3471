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
 * Transport: a udpm:// URL (the default, LCM's) is read and written in this thread (node_udpm.h: the
 * LCM library's receive thread and pipe cost a second thread wake-up per message); any other URL goes
 * through the LCM library. The datagrams are the library's either way.
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
#include "aocs_lcm_event_t.h"
#include "aocs_lcm_command_t.h"
#include "aocs_lcm_sensors_t.h"
#include "aocs_lcm_status_t.h"
#include "node_config.h"
#include "node_core.h"
#include "node_udpm.h"
#include "node_wire.h"

#define CH_SENSORS "AOCS_SENSORS"
#define CH_ACTUATOR "AOCS_ACTUATOR_CMD"
#define CH_COMMAND "AOCS_COMMAND"
#define CH_STATUS "AOCS_STATUS"
#define CH_EVENTS "AOCS_EVENTS"

#define EXIT_CONFIG 2
#define EXIT_RUNTIME 1
#define LCM_WAIT_MAX_MS 100
#define LCM_ERRORS_MAX 100u
#define NS_PER_MS 1000000ull
/* the LCM library's URL when none is configured nor in LCM_DEFAULT_URL (lcm.h) */
#define LCM_URL_DEFAULT "udpm://239.255.76.67:7667?ttl=0"

typedef struct {
    lcm_t *lcm;                   /* the LCM library, for a URL that is not udpm:// (else NULL) */
    int use_udpm;                 /* udpm read and written in this thread (node_udpm.h) */
    node_udpm_t udpm;
    uint8_t enc[NODE_UDPM_DATAGRAM_MAX]; /* an outgoing message, encoded */
    aocs_node_core_t core;        /* the node logic (node_core.h), shared with the in-process node */
    uint64_t t_start_ns;
    uint64_t t_last_sensor_ns;    /* HAL time of the last AOCS_SENSORS message */
    /* real-time mode */
    aocs_node_epoch_t epoch;      /* rotating target: t0 mapped onto the HAL clock */
    int have_new_sample;
    aocs_lcm_sensors_t latest;
    uint64_t latest_rx_ns;
    int64_t latest_tick;
} node_t;

static volatile sig_atomic_t g_stop = 0;
static node_t g_node;                         /* static: the stats ring is large */

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

static int64_t hal_utime(void)
{
    return aocs_node_to_i64(aocs_hal_time_ns() / 1000u);
}

static void publish_actuator(node_t *n, const aocs_lcm_actuator_cmd_t *m)
{
    int rc;
    if (n->use_udpm != 0) {
        const int size = aocs_lcm_actuator_cmd_t_encoded_size(m);
        rc = ((size > 0) && ((size_t)size <= sizeof(n->enc)) &&
              (aocs_lcm_actuator_cmd_t_encode(n->enc, 0, size, m) == size))
                 ? node_udpm_publish(&n->udpm, CH_ACTUATOR, n->enc, (size_t)size)
                 : -1;
    } else {
        rc = aocs_lcm_actuator_cmd_t_publish(n->lcm, CH_ACTUATOR, m);
    }
    if (rc != 0) {
        (void)fprintf(stderr, "fsw_node: publish on %s failed\n", CH_ACTUATOR);
    }
}

/* the events the last step raised (fault management), one event_t each on AOCS_EVENTS */
static void publish_events(node_t *n)
{
    aocs_lcm_event_t e;
    while (aocs_node_core_event(&n->core, &e) != 0) {
        int rc;
        if (n->use_udpm != 0) {
            const int size = aocs_lcm_event_t_encoded_size(&e);
            rc = ((size > 0) && ((size_t)size <= sizeof(n->enc)) && (aocs_lcm_event_t_encode(n->enc, 0, size, &e) == size))
                     ? node_udpm_publish(&n->udpm, CH_EVENTS, n->enc, (size_t)size)
                     : -1;
        } else {
            rc = aocs_lcm_event_t_publish(n->lcm, CH_EVENTS, &e);
        }
        if (rc != 0) {
            (void)fprintf(stderr, "fsw_node: publish on %s failed\n", CH_EVENTS);
        }
    }
}

/* one step of the real-time loop (with the newest sample, or without one) and its command published */
static void step_realtime(node_t *n, const aocs_exec_input_t *in, int deadline_missed)
{
    aocs_lcm_actuator_cmd_t m;
    aocs_node_core_t *c = &n->core;
    const aocs_status_t rc = (in != NULL) ? aocs_exec_step(&c->exec, in, &c->out)
                                          : aocs_exec_step_no_input(&c->exec, &c->out);
    aocs_node_core_record(c, rc);
    aocs_node_core_actuator(c, rc, n->latest_tick, hal_utime(), deadline_missed, &m);
    publish_actuator(n, &m);
    publish_events(n);
}

static void publish_status(node_t *n, int exiting)
{
    aocs_lcm_status_t m;
    int rc;
    aocs_node_core_status(&n->core, exiting, hal_utime(), &m);
    if (n->use_udpm != 0) {
        const int size = aocs_lcm_status_t_encoded_size(&m);
        rc = ((size > 0) && ((size_t)size <= sizeof(n->enc)) && (aocs_lcm_status_t_encode(n->enc, 0, size, &m) == size))
                 ? node_udpm_publish(&n->udpm, CH_STATUS, n->enc, (size_t)size)
                 : -1;
    } else {
        rc = aocs_lcm_status_t_publish(n->lcm, CH_STATUS, &m);
    }
    if (rc != 0) {
        (void)fprintf(stderr, "fsw_node: publish on %s failed\n", CH_STATUS);
    }
}

/* ---- AOCS_SENSORS ------------------------------------------------------- */
static void on_sensors(const void *data, size_t size, void *user)
{
    node_t *n = (node_t *)user;
    n->t_last_sensor_ns = aocs_hal_time_ns();
    if (n->core.cfg.run_mode == AOCS_NODE_RUN_LOCKSTEP) {
        /* bytes in -> actuator_cmd_t out: the one function the in-process node calls too */
        aocs_lcm_actuator_cmd_t m;
        if (aocs_node_core_lockstep(&n->core, data, (uint32_t)size, &m) != 0) {
            publish_actuator(n, &m);
            publish_events(n);
        }
    } else {
        /* real time: keep the newest sample for the next deadline */
        aocs_lcm_sensors_t msg;
        if (aocs_node_core_receive(&n->core, data, (uint32_t)size, &msg) == AOCS_NODE_RX_ACCEPTED) {
            n->latest = msg;
            n->latest_rx_ns = n->t_last_sensor_ns;
            n->latest_tick = msg.tick;
            n->have_new_sample = 1;
            (void)aocs_lcm_sensors_t_decode_cleanup(&msg);
        }
    }
}

/* ---- AOCS_COMMAND ------------------------------------------------------- */
static void on_command(const void *data, size_t size, void *user)
{
    node_t *n = (node_t *)user;
    if (aocs_node_core_command(&n->core, data, (uint32_t)size) == 0) {
        return;
    }
    if (n->core.last_request_status != (int32_t)AOCS_OK) {
        (void)fprintf(stderr, "fsw_node: command %lld rejected: %s\n", (long long)n->core.last_request,
                      aocs_status_name((aocs_status_t)n->core.last_request_status));
    }
    publish_status(n, 0); /* acknowledgement */
}

/* the two handlers as the LCM library calls them (a URL that is not udpm://) */
static void lcm_on_sensors(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    (void)channel;
    on_sensors(rbuf->data, rbuf->data_size, user);
}

static void lcm_on_command(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    (void)channel;
    on_command(rbuf->data, rbuf->data_size, user);
}

/* ---- configuration ------------------------------------------------------ */
static int load_config(node_t *n, const char *path)
{
    char err[AOCS_NODE_ERR_MAX];
    if ((aocs_node_config_load(path, &n->core.cfg, err, sizeof(err)) != 0) ||
        (aocs_node_core_configure(&n->core, path, err, sizeof(err)) != 0)) {
        (void)fprintf(stderr, "fsw_node: config error: %s\n", err);
        return 1;
    }
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
    rc = (n->use_udpm != 0) ? node_udpm_handle_timeout(&n->udpm, ms) : lcm_handle_timeout(n->lcm, ms);
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
    uint64_t idle_ns = seconds_ns(n->core.cfg.idle_timeout_s);
    uint64_t run_ns = seconds_ns(n->core.cfg.run_timeout_s);
    uint64_t status_ns = seconds_ns(n->core.cfg.status_period_s);
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
    aocs_node_core_t *c = &n->core;
    uint64_t run_ns = seconds_ns(c->cfg.run_timeout_s);
    uint64_t status_ns = seconds_ns(c->cfg.status_period_s);
    uint64_t next_status = n->t_start_ns; /* the first heartbeat at once: the plant starts on it */
    uint64_t deadline = n->t_start_ns + c->exec.period_ns;
    unsigned errors = 0u;
    if (aocs_exec_timer_init(&c->timer, c->exec.period_ns, deadline) != AOCS_OK) {
        *failed = 1;
        return "timer_error";
    }
    while (g_stop == 0) {
        uint64_t now = aocs_hal_time_ns();
        uint64_t slips_before;
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
        slips_before = c->timer.slips;
        (void)aocs_exec_timer_period_start(&c->timer, aocs_hal_time_ns(), &deadline);
        missed = (c->timer.slips != slips_before) ? 1 : 0;
        if (n->have_new_sample != 0) {
            aocs_exec_input_t in;
            /* the sensor time base is the HAL clock here: sim time 0 of the plant (the
             * rotating target's t0) is rx time - t_s, set by the first sample and moved
             * only by K consistent later ones (node_wire.h, aocs_node_epoch_update) */
            if (aocs_node_epoch_update(&n->epoch, n->latest_rx_ns, aocs_node_seconds_to_ns(n->latest.t_s),
                                       c->cfg.exec.stale_timeout_ns) != 0) {
                (void)aocs_exec_set_target_epoch(&c->exec, n->epoch.t0_ns);
            }
            aocs_node_sensors_to_input(&n->latest, n->latest_rx_ns, &in);
            n->have_new_sample = 0;
            step_realtime(n, &in, missed);
        } else {
            step_realtime(n, NULL, missed);
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
static void report(node_t *n, const char *reason)
{
    static char json[4096];
    aocs_node_core_t *c = &n->core;
    aocs_node_stats_summary_t s = aocs_node_stats_summary(&c->stats, c->scratch);
    double jitter_rms = (double)aocs_exec_timer_jitter_rms_ns(&c->timer);
    const char *run = (c->cfg.run_mode == AOCS_NODE_RUN_REALTIME) ? "realtime" : "lockstep";
    (void)fprintf(stderr,
                  "fsw_node: %s end (%s): steps=%llu overruns=%llu step_ns median=%llu p99=%llu max=%llu "
                  "jitter_ns max=%llu rms=%.0f lost=%llu dup=%llu jump=%llu seq_resync=%llu exec_resync=%lu "
                  "foreign=%llu malformed=%llu\n",
                  run, reason, (unsigned long long)c->stats.count, (unsigned long long)aocs_node_core_overruns(c),
                  (unsigned long long)s.median, (unsigned long long)s.p99, (unsigned long long)s.max,
                  (unsigned long long)c->timer.jitter_max_abs_ns, jitter_rms, (unsigned long long)c->seq.lost,
                  (unsigned long long)c->seq.duplicate, (unsigned long long)c->seq.jump,
                  (unsigned long long)c->seq.resyncs, (unsigned long)c->exec.accept.resyncs,
                  (unsigned long long)c->n_foreign, (unsigned long long)c->n_malformed);
    (void)aocs_node_core_report_json(c, reason, json, sizeof(json));
    (void)printf("%s\n", json);
    (void)fflush(stdout);
}

/* the bus: a udpm:// URL (configured, else LCM_DEFAULT_URL, else the library's default) read in this thread,
 * any other through the LCM library; 0, or 1 with the reason on stderr */
static int open_transport(node_t *n)
{
    const char *env = getenv("LCM_DEFAULT_URL");
    const char *url = (n->core.cfg.lcm_url[0] != '\0') ? n->core.cfg.lcm_url
                      : ((env != NULL) && (env[0] != '\0')) ? env
                                                            : LCM_URL_DEFAULT;
    if (node_udpm_url_ok(url) != 0) {
        if (node_udpm_open(&n->udpm, url) != 0) {
            (void)fprintf(stderr, "fsw_node: cannot open %s: %s\n", url, strerror(errno));
            return 1;
        }
        n->use_udpm = 1;
        /* lockstep only: a real-time node sleeps between its periods */
        n->udpm.spin_ns = (n->core.cfg.run_mode == AOCS_NODE_RUN_LOCKSTEP)
                              ? (uint64_t)(n->core.cfg.wait_spin_us * 1000.0 + 0.5) : 0u;
        if ((node_udpm_subscribe(&n->udpm, CH_SENSORS, on_sensors, n) != 0) ||
            (node_udpm_subscribe(&n->udpm, CH_COMMAND, on_command, n) != 0)) {
            (void)fprintf(stderr, "fsw_node: udpm subscribe failed\n");
            node_udpm_close(&n->udpm);
            return 1;
        }
        return 0;
    }
    n->lcm = lcm_create(url);
    if (n->lcm == NULL) {
        (void)fprintf(stderr, "fsw_node: lcm_create(%s) failed\n", url);
        return 1;
    }
    if ((lcm_subscribe(n->lcm, CH_SENSORS, lcm_on_sensors, n) == NULL) ||
        (lcm_subscribe(n->lcm, CH_COMMAND, lcm_on_command, n) == NULL)) {
        (void)fprintf(stderr, "fsw_node: lcm_subscribe failed\n");
        lcm_destroy(n->lcm);
        return 1;
    }
    return 0;
}

static void close_transport(node_t *n)
{
    if (n->use_udpm != 0) {
        node_udpm_close(&n->udpm);
    } else {
        lcm_destroy(n->lcm);
    }
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
    aocs_node_core_reset(&n->core);
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

    if (open_transport(n) != 0) {
        return EXIT_RUNTIME;
    }
    (void)fprintf(stderr, "fsw_node: %s, law %s, period %.6f s, ready\n",
                  (n->core.cfg.run_mode == AOCS_NODE_RUN_REALTIME) ? "realtime" : "lockstep",
                  aocs_law_name(n->core.exec.law), (double)n->core.exec.period_ns * 1.0e-9);
    n->t_start_ns = aocs_hal_time_ns();
    if (n->core.cfg.run_mode == AOCS_NODE_RUN_REALTIME) {
        reason = run_realtime(n, &failed);
    } else {
        reason = run_lockstep(n, &failed);
    }
    publish_status(n, 1);
    report(n, reason);
    close_transport(n);
    return (failed != 0) ? EXIT_RUNTIME : 0;
}
