/*
 * libFuzzer target: fsw_node's AOCS_SENSORS path (node_wire.h): decode,
 * frame sequence, sensors_t -> executive input, seconds -> ns, real-time
 * epoch, the star tracker's time of measurement, executive step, for a
 * sequence of payloads. Invariants: nothing crashes or overflows
 * (sanitizers), every step's command is finite and within the limits
 * (fuzz_support.h), the sequence counters only grow, and the tracker's time
 * of measurement is converted as t_s is (lockstep: exactly ns(st_t_meas_s);
 * real time: never ahead of the sample's own reception time by more than
 * the message says, no wrap).
 *
 * Input: u8 mode (bit0 real time, bits1-4 law), then payloads, each as a u16
 * little-endian length and that many bytes (an encoded aocs_lcm sensors_t,
 * or anything). The seed corpus holds real encodings (tests/fuzz/make_corpus.py).
 */
#include "fuzz_support.h"

#include "aocs/hal.h"
#include "node_wire.h"

static uint64_t g_now_ns;

uint64_t aocs_hal_time_ns(void)
{
    g_now_ns += 1000u;
    return g_now_ns;
}

uint32_t aocs_hal_cycles(void)
{
    return 0u;
}

void aocs_hal_sleep_until_ns(uint64_t t_ns)
{
    if (t_ns > g_now_ns) {
        g_now_ns = t_ns;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_reader_t r = {data, size, 0u};
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_node_seq_t seq;
    aocs_node_epoch_t epoch;
    uint8_t mode = fuzz_u8(&r);
    uint8_t buf[65536];
    int frames = 0;

    g_now_ns = 1000000000u;
    aocs_exec_config_default(&cfg);
    fuzz_all_law_configs(&cfg.laws);
    cfg.law = (aocs_law_id_t)((mode >> 1) % (uint8_t)AOCS_LAW_COUNT);
    cfg.u_max_axis = aocs_vec3_make(AOCS_R(0.5), AOCS_R(0.6), AOCS_R(0.7));
    cfg.u_max_norm = AOCS_R(0.8);
    cfg.recover_good_samples = 3u;
    cfg.clock = ((mode & 1u) != 0u) ? AOCS_EXEC_CLOCK_REALTIME : AOCS_EXEC_CLOCK_LOCKSTEP;
    if (aocs_exec_init(&exec, &cfg) != AOCS_OK) {
        abort(); /* a fixed valid configuration */
    }
    aocs_node_seq_reset(&seq);
    memset(&epoch, 0, sizeof(epoch));
    while ((fuzz_more(&r) != 0) && (frames < 1024)) {
        uint16_t len = fuzz_u16(&r);
        size_t avail = r.n - r.pos;
        aocs_lcm_sensors_t msg;
        uint64_t lost = seq.lost;
        uint64_t dup = seq.duplicate;
        if ((size_t)len > avail) {
            len = (uint16_t)avail;
        }
        memcpy(buf, r.p + r.pos, len);
        r.pos += len;
        ++frames;
        if (aocs_node_decode_sensors(buf, len, &msg) != AOCS_NODE_DECODE_OK) {
            continue;
        }
        if (aocs_node_seq_accepted(aocs_node_seq_check(&seq, msg.frame)) != 0) {
            aocs_exec_input_t in;
            uint64_t t_ns;
            if (cfg.clock == AOCS_EXEC_CLOCK_LOCKSTEP) {
                t_ns = aocs_node_seconds_to_ns(msg.t_s);
            } else {
                g_now_ns += 20000000u;
                t_ns = g_now_ns;
                if (aocs_node_epoch_update(&epoch, t_ns, aocs_node_seconds_to_ns(msg.t_s), cfg.stale_timeout_ns) !=
                    0) {
                    (void)aocs_exec_set_target_epoch(&exec, epoch.t0_ns);
                }
            }
            aocs_node_sensors_to_input(&msg, t_ns, &in);
            if (cfg.clock == AOCS_EXEC_CLOCK_LOCKSTEP) {
                if (in.st_t_meas_ns != aocs_node_seconds_to_ns(msg.st_t_meas_s)) {
                    abort(); /* lockstep: converted exactly as t_s is */
                }
            } else if ((in.st_t_meas_ns > t_ns) &&
                       (in.st_t_meas_ns - t_ns > aocs_node_seconds_to_ns(msg.st_t_meas_s))) {
                abort(); /* real time: ahead of the reception by at most its own time */
            }
            if ((((msg.valid & AOCS_LCM_SENSORS_T_VALID_STAR_TRACKER) != 0) ? 1 : 0) !=
                (((in.valid & AOCS_EXEC_VALID_ST) != 0u) ? 1 : 0)) {
                abort();
            }
            if (aocs_exec_step(&exec, &in, &out) != AOCS_OK) {
                abort();
            }
            fuzz_check_output(&cfg, &out);
        }
        if ((seq.lost < lost) || (seq.duplicate < dup)) {
            abort(); /* counters saturate, never wrap */
        }
        (void)aocs_lcm_sensors_t_decode_cleanup(&msg);
    }
    return 0;
}
