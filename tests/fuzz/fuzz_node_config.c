/*
 * libFuzzer target: fsw_node's configuration parser (sil/fsw_node/node_config.c,
 * linked as it is) on the fuzz bytes as the file's contents, then the node's
 * own range checks (node_checks.h) and aocs_exec_init, as fsw_node's
 * load_config does. When the executive accepts the configuration, one step on
 * a fixed sample must give a command within the limits (fuzz_support.h).
 *
 * The parser reads a path, so the bytes go to an in-memory file (memfd)
 * opened through /proc/self/fd: no disk I/O per input.
 */
#define _GNU_SOURCE
#include "fuzz_support.h"

#include <sys/mman.h>
#include <unistd.h>

#include "node_checks.h"
#include "node_config.h"

static int g_fd = -1;
static char g_path[64];

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static aocs_node_config_t cfg; /* large (gain tables): not on the stack */
    char err[AOCS_NODE_ERR_MAX];
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_exec_input_t in;
    if (g_fd < 0) {
        g_fd = memfd_create("fuzz_node_config", 0);
        if (g_fd < 0) {
            abort();
        }
        (void)snprintf(g_path, sizeof(g_path), "/proc/self/fd/%d", g_fd);
    }
    if ((ftruncate(g_fd, 0) != 0) || (pwrite(g_fd, data, size, 0) != (ssize_t)size)) {
        abort();
    }
    err[0] = '\0';
    if (aocs_node_config_load(g_path, &cfg, err, sizeof(err)) != 0) {
        if ((err[0] == '\0') || (memchr(err, '\0', sizeof(err)) == NULL)) {
            abort(); /* every refusal names its reason */
        }
        return 0;
    }
    if (aocs_node_timeouts_check(&cfg, err, sizeof(err)) != 0) {
        return 0;
    }
    if (aocs_exec_init(&exec, &cfg.exec) != AOCS_OK) {
        return 0;
    }
    memset(&in, 0, sizeof(in));
    in.tick = 1u;
    in.t_sensor_ns = exec.period_ns;
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE | AOCS_EXEC_VALID_ORBIT;
    in.q_BN = aocs_quat_make(AOCS_R(0.1), AOCS_R(-0.2), AOCS_R(0.3), AOCS_R(0.9273618495495703));
    in.w_BN_B = aocs_vec3_make(AOCS_R(0.5), AOCS_R(-0.2), AOCS_R(0.03));
    in.pos_m = aocs_vec3_make(AOCS_R(100.0), AOCS_R(-5.0), AOCS_R(1.0));
    in.vel_mps = aocs_vec3_make(AOCS_R(0.1), AOCS_R(0.0), AOCS_R(-0.1));
    cfg.exec.clock = AOCS_EXEC_CLOCK_LOCKSTEP; /* the real-time bounds need the HAL clock: lockstep here */
    if (aocs_exec_init(&exec, &cfg.exec) != AOCS_OK) {
        return 0;
    }
    if (aocs_exec_step(&exec, &in, &out) != AOCS_OK) {
        abort();
    }
    fuzz_check_output(&cfg.exec, &out);
    return 0;
}
