/*
 * libFuzzer target: the in-process node's C ABI (sil/fsw_node/direct/aocs_node_direct.h) over the shared
 * node logic (node_core.c): a node opened on a real configuration (irassi_large, quat_pd with slew
 * guidance, 0.5 N m per axis), then a sequence of AOCS_SENSORS and AOCS_COMMAND payloads as the plant would
 * hand them. Invariants: nothing crashes or overflows (sanitizers); every reply decodes as an
 * actuator_cmd_t (resp. status_t) of exactly the returned length, with its tick the payload's, finite
 * commands within 0.5 N m per axis, and counters that only grow; a payload that gets no reply moves the
 * malformed / foreign / duplicate counts; the slot is freed and a second open succeeds.
 *
 * Input: payloads, each a u8 kind (bit0: command, else sensors), a u16 little-endian length and that many
 * bytes (an encoded sensors_t / command_t, or anything). Seeds: tests/fuzz/corpus/fuzz_node_direct
 * (the real encodings of fuzz_sensors and fuzz_commands).
 */
#include "fuzz_support.h"

#include "aocs_lcm_actuator_cmd_t.h"
#include "aocs_lcm_sensors_t.h"
#include "aocs_lcm_status_t.h"
#include "aocs_node_direct.h"

static const char CONFIG[] =
    "law = quat_pd\n"
    "mode = lockstep\n"
    "control_period_s = 0.1\n"
    "target_q = 0.05324287195458452 -0.16550059233095835 0.2563410097183341 0.9508228211715969\n"
    "inertia = 2059.5 0.0 0.0 0.0 5954.2 0.0 0.0 0.0 5974.3\n"
    "k_safe = 466.2666666666667\n"
    "u_max_axis = 0.5 0.5 0.5\n"
    "guidance.mode = slew\n"
    "guidance.profile = bang_coast_bang\n"
    "guidance.margin = 0.8\n"
    "quat_pd.kp = 4000.0\n"
    "quat_pd.kd = 8000.0\n"
    "idle_timeout_s = 5.0\n"
    "run_timeout_s = 0.0\n"
    "status_period_s = 0.05\n";

#define U_MAX 0.5

static void check_reply(const uint8_t *out, int32_t n, const aocs_lcm_actuator_cmd_t *prev, int have_prev,
                        aocs_lcm_actuator_cmd_t *m)
{
    if (aocs_lcm_actuator_cmd_t_decode(out, 0, n, m) != n) {
        abort(); /* the reply is one whole actuator_cmd_t */
    }
    for (int i = 0; i < 3; ++i) {
        if (!isfinite(m->u_sat[i]) || !(fabs(m->u_sat[i]) <= U_MAX)) {
            abort();
        }
    }
    if ((have_prev != 0) &&
        ((m->frame != prev->frame + 1) || (m->n_malformed < prev->n_malformed) || (m->n_foreign < prev->n_foreign) ||
         (m->n_duplicate < prev->n_duplicate) || (m->n_cmd_accepted < prev->n_cmd_accepted))) {
        abort(); /* our frame counter steps by one; the counts only grow */
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_reader_t r = {data, size, 0u};
    static uint8_t buf[65536];
    static uint8_t out[4096];
    char err[512];
    aocs_lcm_actuator_cmd_t prev;
    int have_prev = 0;
    int frames = 0;
    const int32_t h = aocs_direct_open(CONFIG, "fuzz.cfg", err, sizeof(err));
    if (h < 0) {
        abort(); /* a fixed valid configuration */
    }
    memset(&prev, 0, sizeof(prev));
    while ((fuzz_more(&r) != 0) && (frames < 512)) {
        const uint8_t kind = fuzz_u8(&r);
        const uint16_t len = fuzz_chunk(&r, buf);
        int32_t n;
        ++frames;
        if ((kind & 1u) != 0u) {
            aocs_lcm_status_t st;
            n = aocs_direct_command(h, buf, len, 7, out, sizeof(out));
            if ((n < 0) || ((n > 0) && (aocs_lcm_status_t_decode(out, 0, n, &st) != n))) {
                abort();
            }
        } else {
            aocs_lcm_sensors_t in;
            aocs_lcm_actuator_cmd_t m;
            n = aocs_direct_sensors(h, buf, len, out, sizeof(out));
            if (n < 0) {
                abort();
            }
            if (n > 0) {
                if (aocs_lcm_sensors_t_decode(buf, 0, len, &in) != (int)len) {
                    abort(); /* only a whole sensors_t gets a reply */
                }
                check_reply(out, n, &prev, have_prev, &m);
                if (m.tick != in.tick) {
                    abort(); /* the reply is the payload's step */
                }
                (void)aocs_lcm_sensors_t_decode_cleanup(&in);
                (void)aocs_lcm_actuator_cmd_t_decode_cleanup(&prev);
                prev = m;
                have_prev = 1;
            }
        }
    }
    if (have_prev != 0) {
        (void)aocs_lcm_actuator_cmd_t_decode_cleanup(&prev);
    }
    if ((aocs_direct_report(h, "fuzz", (char *)out, sizeof(out)) <= 0) || (aocs_direct_close(h) != 0) ||
        (aocs_direct_close(h) != -1)) {
        abort(); /* a report, a close, and a second close refused */
    }
    return 0;
}
