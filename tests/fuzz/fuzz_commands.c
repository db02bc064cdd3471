/*
 * libFuzzer target: fsw_node's AOCS_COMMAND path (node_wire.h): decode and
 * aocs_node_command_apply (law / mode / target onto aocs_exec_select) on an
 * executive that has a valid configuration of every law, with a good sample
 * stepped after each command. Invariants: no crash or UB (sanitizers), the
 * command of every step finite and within the limits (fuzz_support.h), and
 * a rejected command changes neither the law nor the mode.
 *
 * Input: u8 initial law, then payloads, each a u16 little-endian length and
 * that many bytes (an encoded aocs_lcm command_t, or anything).
 */
#include "fuzz_support.h"

#include "node_wire.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_reader_t r = {data, size, 0u};
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_law_id_t nominal;
    uint8_t buf[65536];
    uint32_t tick = 0u;
    int frames = 0;

    aocs_exec_config_default(&cfg);
    fuzz_all_law_configs(&cfg.laws);
    cfg.law = (aocs_law_id_t)(fuzz_u8(&r) % (uint8_t)AOCS_LAW_COUNT);
    cfg.u_max_axis = aocs_vec3_make(AOCS_R(0.5), AOCS_R(0.6), AOCS_R(0.7));
    cfg.recover_good_samples = 2u;
    if (aocs_exec_init(&exec, &cfg) != AOCS_OK) {
        abort();
    }
    nominal = cfg.law;
    while ((fuzz_more(&r) != 0) && (frames < 1024)) {
        uint16_t len = fuzz_u16(&r);
        size_t avail = r.n - r.pos;
        aocs_lcm_command_t msg;
        aocs_exec_input_t in;
        if ((size_t)len > avail) {
            len = (uint16_t)avail;
        }
        memcpy(buf, r.p + r.pos, len);
        r.pos += len;
        ++frames;
        if (aocs_node_decode_command(buf, len, &msg) == AOCS_NODE_DECODE_OK) {
            const aocs_law_id_t law_before = exec.law;
            const aocs_exec_mode_t mode_before = exec.mode;
            if (aocs_node_command_apply(&exec, &nominal, &msg) != AOCS_OK) {
                if ((exec.law != law_before) || (exec.mode != mode_before)) {
                    abort(); /* a rejected command changes nothing */
                }
            }
            (void)aocs_lcm_command_t_decode_cleanup(&msg);
        }
        /* one good sample of the current kind (attitude and orbit flags both set) */
        memset(&in, 0, sizeof(in));
        tick += 1u;
        in.tick = tick;
        in.t_sensor_ns = (uint64_t)tick * exec.period_ns;
        in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE | AOCS_EXEC_VALID_ORBIT;
        in.q_BN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0871557427), AOCS_R(0.9961946981));
        in.w_BN_B = aocs_vec3_make(AOCS_R(0.01), AOCS_R(-0.02), AOCS_R(0.03));
        in.pos_m = aocs_vec3_make(AOCS_R(10.0), AOCS_R(-5.0), AOCS_R(1.0));
        in.vel_mps = aocs_vec3_make(AOCS_R(0.01), AOCS_R(0.0), AOCS_R(-0.01));
        if (aocs_exec_step(&exec, &in, &out) != AOCS_OK) {
            abort();
        }
        fuzz_check_output(&cfg, &out);
    }
    return 0;
}
