/*
 * aocs_node_input: the executive inputs fsw_node makes of the AOCS_SENSORS
 * messages of an LCM log, for the tests of the wire contract (what the flight
 * software is given, not only what the plant sent).
 *
 *   aocs_node_input LOG      one JSON line per AOCS_SENSORS event of LOG
 *
 * Each event goes through fsw_node's own lockstep path (node_wire.c):
 * aocs_node_decode_sensors, the frame sequence check, and
 * aocs_node_lockstep_input. A line: {"event": N, "decode": "ok" | "malformed"
 * | "foreign", and when decoded "accepted": whether the frame sequence lets
 * fsw_node step on it, then the aocs_exec_input_t: "tick", "t_sensor_ns",
 * "valid" (AOCS_EXEC_VALID_* bits), "q", "w", "pos", "vel", "wheel_speed",
 * "st_q", "st_t_meas_ns", "gyro_w", "mag_b_t"}. Reals with 17 significant digits (NaN,
 * Infinity as Python's json reads them). Exit 2 on usage or an unreadable log.
 * Host tool (stdio).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <lcm/eventlog.h>

#include "node_wire.h"

#define EXIT_USAGE 2

static void put_real(double x)
{
    if (isnan(x) != 0) {
        (void)fputs("NaN", stdout);
    } else if (isinf(x) != 0) {
        (void)fputs((x > 0.0) ? "Infinity" : "-Infinity", stdout);
    } else {
        (void)printf("%.17g", x);
    }
}

static void put_reals(const char *name, const real_t *x, int n)
{
    (void)printf(", \"%s\": [", name);
    for (int i = 0; i < n; ++i) {
        if (i > 0) {
            (void)fputs(", ", stdout);
        }
        put_real((double)x[i]);
    }
    (void)putchar(']');
}

static void put_input(const aocs_exec_input_t *in)
{
    (void)printf(", \"tick\": %lu, \"t_sensor_ns\": %llu, \"valid\": %lu", (unsigned long)in->tick,
                 (unsigned long long)in->t_sensor_ns, (unsigned long)in->valid);
    put_reals("q", in->q_BN.q, 4);
    put_reals("w", in->w_BN_B.v, 3);
    put_reals("pos", in->pos_m.v, 3);
    put_reals("vel", in->vel_mps.v, 3);
    put_reals("wheel_speed", in->wheel_speed_radps, (int)AOCS_WHEELS_MAX);
    put_reals("st_q", in->st_q_SN.q, 4);
    (void)printf(", \"st_t_meas_ns\": %llu", (unsigned long long)in->st_t_meas_ns);
    put_reals("gyro_w", in->gyro_w_B.v, 3);
    put_reals("mag_b_t", in->mag_B_T.v, 3);
}

int main(int argc, char **argv)
{
    lcm_eventlog_t *log;
    lcm_eventlog_event_t *ev;
    aocs_node_seq_t seq;
    if (argc != 2) {
        (void)fprintf(stderr, "usage: aocs_node_input LOG\n");
        return EXIT_USAGE;
    }
    log = lcm_eventlog_create(argv[1], "r");
    if (log == NULL) {
        (void)fprintf(stderr, "aocs_node_input: cannot read %s\n", argv[1]);
        return EXIT_USAGE;
    }
    aocs_node_seq_reset(&seq);
    while ((ev = lcm_eventlog_read_next_event(log)) != NULL) {
        if ((ev->channellen == (int32_t)strlen("AOCS_SENSORS")) && (strcmp(ev->channel, "AOCS_SENSORS") == 0)) {
            aocs_lcm_sensors_t msg;
            const aocs_node_decode_t d = aocs_node_decode_sensors(ev->data, (uint32_t)ev->datalen, &msg);
            (void)printf("{\"event\": %lld, \"decode\": \"%s\"", (long long)ev->eventnum,
                         (d == AOCS_NODE_DECODE_OK) ? "ok" : ((d == AOCS_NODE_DECODE_FOREIGN) ? "foreign" : "malformed"));
            if (d == AOCS_NODE_DECODE_OK) {
                aocs_exec_input_t in;
                const int accepted = aocs_node_seq_accepted(aocs_node_seq_check(&seq, msg.frame));
                aocs_node_lockstep_input(&msg, &in);
                (void)printf(", \"accepted\": %s", (accepted != 0) ? "true" : "false");
                put_input(&in);
                (void)aocs_lcm_sensors_t_decode_cleanup(&msg);
            }
            (void)fputs("}\n", stdout);
        }
        lcm_eventlog_free_event(ev);
    }
    lcm_eventlog_destroy(log);
    return 0;
}
